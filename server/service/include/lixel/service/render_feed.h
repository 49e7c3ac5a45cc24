// The hand-off between a Render job on a GPU worker and the call's writer: the header goes out
// as soon as the plan exists and each image's chunks as soon as it is read back, with at most
// one image on the host at a time (the one being written), so a call's peak memory is its
// largest image plus one chunk message, whatever the plan's total.
#pragma once

#include <grpcpp/support/status.h>
#include <lixel/render/image.h>
#include <lixel/v1/lixel.pb.h>

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>

namespace lixel::service {

// Writes chunk `offset` of image `image_index` (at most `chunk_bytes` of its bytes) into
// `message`, reusing the chunk's buffer when `message` already holds a chunk.
void FillMapChunk(std::uint32_t image_index, const render::FloatImage& image,
                  std::uint64_t offset, std::uint64_t chunk_bytes, v1::RenderChunk* message);
// The same for a coded image's bytes.
void FillMapChunk(std::uint32_t image_index, std::string_view coded, std::uint64_t offset,
                  std::uint64_t chunk_bytes, v1::RenderChunk* message);

class RenderFeed {
  public:
    // `wake` is called (outside the feed's lock, on the producer's thread) when the writer was
    // idle and a message or the end is ready: it should call Next and write what it gets.
    RenderFeed(std::uint64_t chunk_bytes, std::function<void()> wake)
        : chunk_bytes_(chunk_bytes == 0 ? 1 : chunk_bytes), wake_(std::move(wake)) {}

    // Producer (the GPU worker). False once the call has ended (Close): stop rendering.
    bool PutHeader(v1::RenderChunk header);
    // Waits until no image is on the host: kRoom when the next image may be read back;
    // kEnded when the call ended or `cancelled()` (checked every 20 ms); kStalled when the
    // writer took no message for `idle_seconds`.
    enum class Room { kRoom, kEnded, kStalled };
    Room WaitForRoom(const std::function<bool()>& cancelled, double idle_seconds);
    // The pixels of the image written last, to read the next one into (empty when none).
    std::vector<float> TakeSpare();
    bool PutImage(std::uint32_t image_index, render::FloatImage image);
    // A coded image (RenderRequest.encoding): its bytes are written as they are.
    bool PutCoded(std::uint32_t image_index, std::string coded);
    // The job's end; the writer finishes the call with `status` once everything before it is
    // written (an error ends the call at once).
    void Finish(const grpc::Status& status);

    // Writer, when no write is outstanding.
    enum class Step { kWrite, kIdle, kFinish };
    // kWrite: `message` holds the next message to write. kIdle: nothing yet; `wake` will be
    // called. kFinish: `status` ends the call.
    Step Next(v1::RenderChunk* message, grpc::Status* status);
    // The call ended (cancelled, or the client went away): the producer stops.
    void Close();

    std::uint64_t messages() const;

  private:
    bool ReadyLocked() const;
    // Waits until no image is being written; false once the call has ended.
    bool WaitToPutLocked(std::unique_lock<std::mutex>& lock);
    void WakeIfIdle(std::unique_lock<std::mutex>& lock);

    const std::uint64_t chunk_bytes_;
    const std::function<void()> wake_;
    mutable std::mutex mutex_;
    std::condition_variable room_;
    std::optional<v1::RenderChunk> header_;
    std::optional<render::FloatImage> image_;  // the image being written
    std::optional<std::string> coded_;         // or the coded image being written
    std::vector<float> spare_;                 // the last written image's pixels, kept for reuse
    std::uint32_t image_index_ = 0;
    std::uint64_t offset_ = 0;  // next byte of image_ to write
    std::optional<grpc::Status> finish_;
    bool closed_ = false;
    bool idle_ = true;  // the writer waits for wake
    std::uint64_t messages_ = 0;
    std::chrono::steady_clock::time_point last_taken_ = std::chrono::steady_clock::now();
};

}  // namespace lixel::service
