// Bounded worker pool.
#include <lixel/service/work_pool.h>

namespace lixel::service {

WorkPool::WorkPool(int workers, std::size_t capacity, std::function<void(int)> start,
                   std::function<void(int)> stop)
    : capacity_(capacity), start_(std::move(start)), stop_(std::move(stop)) {
    for (int i = 0; i < workers; ++i) threads_.emplace_back([this, i] { Run(i); });
}

WorkPool::~WorkPool() {
    {
        std::lock_guard lock(mutex_);
        stopping_ = true;
    }
    ready_.notify_all();
    for (std::thread& t : threads_) t.join();
}

bool WorkPool::TrySubmit(Task task) {
    {
        std::lock_guard lock(mutex_);
        if (stopping_ || queue_.size() >= capacity_) return false;
        queue_.push_back(std::move(task));
    }
    ready_.notify_one();
    return true;
}

std::size_t WorkPool::queued() const {
    std::lock_guard lock(mutex_);
    return queue_.size();
}

void WorkPool::Run(int worker) {
    if (start_) start_(worker);
    for (;;) {
        Task task;
        {
            std::unique_lock lock(mutex_);
            ready_.wait(lock, [this] { return stopping_ || !queue_.empty(); });
            if (queue_.empty()) break;  // stopping, and nothing left to finish
            task = std::move(queue_.front());
            queue_.pop_front();
        }
        task(worker);
    }
    if (stop_) stop_(worker);
}

}  // namespace lixel::service
