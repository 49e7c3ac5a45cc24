// Assembles the messages of one UploadScene stream (lixel.proto, SceneChunk): a header first,
// then data chunks, in order, adding up to exactly header.total_bytes. It holds no gRPC state:
// the upload reactor feeds it what it reads, and fuzz/fuzz_upload.cc feeds it any sequence.
#pragma once

#include <grpcpp/support/status.h>
#include <lixel/v1/lixel.pb.h>

#include <cstddef>
#include <cstdint>
#include <string>

namespace lixel::service {

class UploadAssembler {
public:
    explicit UploadAssembler(std::uint64_t max_upload_bytes) : max_bytes_(max_upload_bytes) {}

    // One message read from the stream: OK to read on, else the status that ends the call
    // (INVALID_ARGUMENT naming chunks[i] or header.total_bytes, or RESOURCE_EXHAUSTED for an
    // announced size over the upload limit). Nothing may be added after an error.
    grpc::Status Add(const v1::SceneChunk& chunk);
    // The client finished sending: OK when the header and every announced byte arrived.
    grpc::Status Finish() const;

    bool has_header() const noexcept { return has_header_; }
    const v1::SceneHeader& header() const noexcept { return header_; }
    const std::string& content() const noexcept { return content_; }
    std::size_t messages() const noexcept { return messages_; }

private:
    std::uint64_t max_bytes_;
    v1::SceneHeader header_;
    bool has_header_ = false;
    std::size_t messages_ = 0;
    std::string content_;
};

}  // namespace lixel::service
