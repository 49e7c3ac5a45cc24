// fuzz_upload: the UploadScene stream as the service receives it. The input is the upload limit
// (two bytes, in KiB, at least 1) and then records: a kind byte, a little-endian 16-bit length
// and that many bytes. An even kind is a header message whose bytes are parsed as a
// lixel.v1.SceneHeader (any format, size and planes); an odd kind a data chunk. Records go
// through UploadAssembler as the upload reactor feeds it; when every one is accepted, the stream
// is finished and, when complete, decoded into a scene cache by UploadJob, as the service does.
// Checks: refusals are INVALID_ARGUMENT or RESOURCE_EXHAUSTED with a message; accepted content
// is exactly the announced size within the limit; an accepted scene is in the cache with usable
// meshes, and uploading the same bytes again gives the same id, already present.
#include "fuzz_input.h"

#include <lixel/service/jobs.h>
#include <lixel/service/upload_assembler.h>

#include <cstddef>
#include <cstdint>
#include <string>

namespace lixel::fuzz {
namespace {

void CheckRefusal(const grpc::Status& status) {
    if (status.error_code() != grpc::StatusCode::INVALID_ARGUMENT &&
        status.error_code() != grpc::StatusCode::RESOURCE_EXHAUSTED) {
        Fail("upload refused with a status other than INVALID_ARGUMENT or RESOURCE_EXHAUSTED");
    }
    if (status.error_message().empty()) Fail("upload refused without a message");
}

service::ServiceState& State() {
    static service::ServiceState state = [] {
        service::ServiceOptions options;
        options.scene_cache_bytes = 64ull << 20;
        // Small enough that no 4 KiB input decodes past the fuzzer's RSS or time limits.
        options.max_upload_vertices = 1u << 20;
        options.max_upload_triangles = 1u << 20;
        options.max_upload_json_values = 1u << 18;
        return service::ServiceState(options, "");
    }();
    return state;
}

}  // namespace
}  // namespace lixel::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace lixel;
    if (size < 2) return 0;
    const std::uint64_t limit = (std::uint64_t{data[0]} | std::uint64_t{data[1]} << 8) * 1024 + 1024;
    service::UploadAssembler upload(limit);
    std::size_t at = 2;
    while (at + 3 <= size) {
        const std::uint8_t kind = data[at];
        const std::size_t length = std::min<std::size_t>(
            data[at + 1] | static_cast<std::size_t>(data[at + 2]) << 8, size - at - 3);
        const auto* bytes = data + at + 3;
        at += 3 + length;
        v1::SceneChunk chunk;
        if (kind % 2 == 0) {
            // An unparsable header is what gRPC refuses before the reactor: skip it.
            if (!chunk.mutable_header()->ParseFromArray(bytes, static_cast<int>(length))) continue;
        } else {
            chunk.set_data(bytes, length);
        }
        if (const grpc::Status added = upload.Add(chunk); !added.ok()) {
            fuzz::CheckRefusal(added);
            return 0;
        }
    }
    if (const grpc::Status finished = upload.Finish(); !finished.ok()) {
        fuzz::CheckRefusal(finished);
        return 0;
    }
    if (upload.content().size() != upload.header().total_bytes() ||
        upload.content().size() > limit) {
        fuzz::Fail("accepted content is not the announced size within the limit");
    }
    service::ServiceState& state = fuzz::State();
    v1::UploadSceneResponse response;
    const grpc::Status decoded =
        service::UploadJob(state, upload.header(), upload.content(), &response);
    if (!decoded.ok()) {
        fuzz::CheckRefusal(decoded);
        return 0;
    }
    const auto scene = state.cache.Get(response.scene_id());
    if (scene == nullptr) fuzz::Fail("an accepted scene is not in the cache");
    fuzz::CheckMeshes(scene->scene.meshes);
    v1::UploadSceneResponse again;
    if (!service::UploadJob(state, upload.header(), upload.content(), &again).ok() ||
        again.scene_id() != response.scene_id() || !again.already_present()) {
        fuzz::Fail("the same upload twice did not give the same id, already present");
    }
    return 0;
}
