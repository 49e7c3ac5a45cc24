// A fixed set of worker threads behind a bounded queue (DESIGN §8): a full queue refuses work at
// once (the caller answers RESOURCE_EXHAUSTED) instead of letting latency grow without bound.
// Each worker runs `start` once on its own thread before taking work, which is where a worker's
// GL context is made current and its renderer built.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace lixel::service {

class WorkPool {
public:
    using Task = std::function<void(int worker)>;

    // `start` runs on each worker thread before its first task, `stop` after its last one, before
    // the thread (and its thread_local state, such as a GL context) ends.
    WorkPool(int workers, std::size_t capacity, std::function<void(int worker)> start = {},
             std::function<void(int worker)> stop = {});
    ~WorkPool();
    WorkPool(const WorkPool&) = delete;
    WorkPool& operator=(const WorkPool&) = delete;

    // False when `capacity` tasks are already waiting.
    bool TrySubmit(Task task);

    std::size_t queued() const;
    int workers() const noexcept { return static_cast<int>(threads_.size()); }

private:
    void Run(int worker);

    const std::size_t capacity_;
    std::function<void(int)> start_;
    std::function<void(int)> stop_;
    mutable std::mutex mutex_;
    std::condition_variable ready_;
    std::deque<Task> queue_;
    bool stopping_ = false;
    std::vector<std::thread> threads_;
};

}  // namespace lixel::service
