// Render's streaming hand-off.
#include <lixel/service/render_feed.h>

#include <algorithm>
#include <chrono>
#include <utility>

namespace lixel::service {

void FillMapChunk(std::uint32_t image_index, const render::FloatImage& image,
                  std::uint64_t offset, std::uint64_t chunk_bytes, v1::RenderChunk* message) {
    const auto* data = reinterpret_cast<const char*>(image.pixels.data());
    const std::uint64_t size = image.pixels.size() * sizeof(float);
    v1::MapChunk* mc = message->mutable_chunk();
    mc->set_image_index(image_index);
    mc->set_offset(offset);
    // assign, not set_data: the string keeps its capacity from the last chunk, so a stream of
    // 1 MiB chunks allocates (and page-faults in) one buffer, not one per chunk.
    mc->mutable_data()->assign(data + offset, std::min(chunk_bytes, size - offset));
}

void FillMapChunk(std::uint32_t image_index, std::string_view coded, std::uint64_t offset,
                  std::uint64_t chunk_bytes, v1::RenderChunk* message) {
    v1::MapChunk* mc = message->mutable_chunk();
    mc->set_image_index(image_index);
    mc->set_offset(offset);
    mc->mutable_data()->assign(coded.substr(offset, chunk_bytes));
}

bool RenderFeed::PutHeader(v1::RenderChunk header) {
    std::unique_lock lock(mutex_);
    if (closed_) return false;
    header_ = std::move(header);
    WakeIfIdle(lock);
    return true;
}

RenderFeed::Room RenderFeed::WaitForRoom(const std::function<bool()>& cancelled,
                                         double idle_seconds) {
    std::unique_lock lock(mutex_);
    const auto idle = std::chrono::duration<double>(idle_seconds);
    while (!closed_ && (image_.has_value() || coded_.has_value())) {
        if (cancelled && cancelled()) return Room::kEnded;
        if (std::chrono::steady_clock::now() - last_taken_ > idle) return Room::kStalled;
        room_.wait_for(lock, std::chrono::milliseconds(20));
    }
    return closed_ ? Room::kEnded : Room::kRoom;
}

std::vector<float> RenderFeed::TakeSpare() {
    std::lock_guard lock(mutex_);
    return std::exchange(spare_, {});
}

bool RenderFeed::WaitToPutLocked(std::unique_lock<std::mutex>& lock) {
    room_.wait(lock, [&] { return closed_ || (!image_.has_value() && !coded_.has_value()); });
    return !closed_;
}

bool RenderFeed::PutImage(std::uint32_t image_index, render::FloatImage image) {
    std::unique_lock lock(mutex_);
    if (!WaitToPutLocked(lock)) return false;
    image_ = std::move(image);
    image_index_ = image_index;
    offset_ = 0;
    if (image_->pixels.empty()) image_.reset();  // nothing to write: the header says 0 bytes
    WakeIfIdle(lock);
    return true;
}

bool RenderFeed::PutCoded(std::uint32_t image_index, std::string coded) {
    std::unique_lock lock(mutex_);
    if (!WaitToPutLocked(lock)) return false;
    coded_ = std::move(coded);
    image_index_ = image_index;
    offset_ = 0;
    if (coded_->empty()) coded_.reset();
    WakeIfIdle(lock);
    return true;
}

void RenderFeed::Finish(const grpc::Status& status) {
    std::unique_lock lock(mutex_);
    if (finish_) return;
    finish_ = status;
    if (!status.ok()) {  // an error ends the call now: drop what was not written
        header_.reset();
        image_.reset();
        coded_.reset();
        room_.notify_all();
    }
    WakeIfIdle(lock);
}

bool RenderFeed::ReadyLocked() const {
    return header_.has_value() || image_.has_value() || coded_.has_value() || finish_.has_value();
}

void RenderFeed::WakeIfIdle(std::unique_lock<std::mutex>& lock) {
    // Even once closed: the writer must still finish the call.
    if (!idle_ || !ReadyLocked()) return;
    idle_ = false;
    lock.unlock();
    wake_();
}

RenderFeed::Step RenderFeed::Next(v1::RenderChunk* message, grpc::Status* status) {
    std::lock_guard lock(mutex_);
    last_taken_ = std::chrono::steady_clock::now();
    if (header_) {
        *message = std::move(*header_);
        header_.reset();
        ++messages_;
        return Step::kWrite;
    }
    if (image_) {
        FillMapChunk(image_index_, *image_, offset_, chunk_bytes_, message);
        offset_ += message->chunk().data().size();
        if (offset_ >= image_->pixels.size() * sizeof(float)) {
            spare_ = std::move(image_->pixels);
            image_.reset();  // its last chunk is a message of its own now
            room_.notify_all();
        }
        ++messages_;
        return Step::kWrite;
    }
    if (coded_) {
        FillMapChunk(image_index_, *coded_, offset_, chunk_bytes_, message);
        offset_ += message->chunk().data().size();
        if (offset_ >= coded_->size()) {
            coded_.reset();
            room_.notify_all();
        }
        ++messages_;
        return Step::kWrite;
    }
    if (finish_) {
        *status = *finish_;
        return Step::kFinish;
    }
    idle_ = true;
    return Step::kIdle;
}

void RenderFeed::Close() {
    std::lock_guard lock(mutex_);
    closed_ = true;
    image_.reset();
    coded_.reset();
    spare_ = {};
    header_.reset();
    room_.notify_all();
}

std::uint64_t RenderFeed::messages() const {
    std::lock_guard lock(mutex_);
    return messages_;
}

}  // namespace lixel::service
