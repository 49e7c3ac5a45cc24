// The UploadScene stream's order and size rules (upload_assembler.h).
#include <lixel/service/upload_assembler.h>

#include <lixel/service/jobs.h>

namespace lixel::service {

grpc::Status UploadAssembler::Add(const v1::SceneChunk& chunk) {
    const std::string field = "chunks[" + std::to_string(messages_) + "]";
    if (!has_header_) {
        if (!chunk.has_header()) return InvalidArgument(Error{field, "must be the header"});
        header_ = chunk.header();
        has_header_ = true;
        if (header_.total_bytes() == 0) {
            return InvalidArgument(Error{"header.total_bytes", "must be at least 1"});
        }
        if (header_.total_bytes() > max_bytes_) {
            return grpc::Status(grpc::StatusCode::RESOURCE_EXHAUSTED,
                                "header.total_bytes: " + std::to_string(header_.total_bytes()) +
                                    " bytes, over the upload limit of " +
                                    std::to_string(max_bytes_));
        }
        content_.reserve(header_.total_bytes());
    } else {
        if (chunk.has_header()) return InvalidArgument(Error{field, "a second header"});
        if (content_.size() + chunk.data().size() > header_.total_bytes()) {
            return InvalidArgument(Error{field, "more bytes than header.total_bytes announced"});
        }
        content_ += chunk.data();
    }
    ++messages_;
    return grpc::Status::OK;
}

grpc::Status UploadAssembler::Finish() const {
    if (!has_header_) return InvalidArgument(Error{"chunks", "empty upload: no header"});
    if (content_.size() != header_.total_bytes()) {
        return InvalidArgument(Error{"chunks", "ended after " + std::to_string(content_.size()) +
                                                   " of " + std::to_string(header_.total_bytes()) +
                                                   " bytes"});
    }
    return grpc::Status::OK;
}

}  // namespace lixel::service
