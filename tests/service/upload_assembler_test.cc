// Tests for the UploadScene stream's rules (lixel/service/upload_assembler.h): a header first,
// then data in order adding up to exactly the announced size, within the upload limit.
#include <lixel/service/upload_assembler.h>

#include <gtest/gtest.h>

namespace lixel {
namespace {

using service::UploadAssembler;

v1::SceneChunk Header(std::uint64_t total_bytes) {
    v1::SceneChunk chunk;
    chunk.mutable_header()->set_format(v1::SCENE_FORMAT_OBJ);
    chunk.mutable_header()->set_total_bytes(total_bytes);
    return chunk;
}

v1::SceneChunk Data(const std::string& bytes) {
    v1::SceneChunk chunk;
    chunk.set_data(bytes);
    return chunk;
}

TEST(UploadAssembler, AHeaderThenChunksAddingUpToTheAnnouncedSize) {
    UploadAssembler upload(100);
    ASSERT_TRUE(upload.Add(Header(11)).ok());
    ASSERT_TRUE(upload.Add(Data("v 0 ")).ok());
    ASSERT_TRUE(upload.Add(Data("")).ok());  // empty chunks are allowed
    EXPECT_EQ(upload.Finish().error_message(), "chunks: ended after 4 of 11 bytes");
    ASSERT_TRUE(upload.Add(Data("0 0\nv 1")).ok());
    EXPECT_TRUE(upload.Finish().ok());
    EXPECT_EQ(upload.content(), "v 0 0 0\nv 1");
    EXPECT_EQ(upload.header().format(), v1::SCENE_FORMAT_OBJ);
    EXPECT_EQ(upload.messages(), 4u);
}

TEST(UploadAssembler, OutOfOrderOrOversizedStreamsAreRefusedNamingTheMessage) {
    struct Case {
        std::vector<v1::SceneChunk> messages;
        grpc::StatusCode code;
        const char* message;
    };
    const Case cases[] = {
        {{Data("v 0 0 0")}, grpc::StatusCode::INVALID_ARGUMENT, "chunks[0]: must be the header"},
        {{Header(0)}, grpc::StatusCode::INVALID_ARGUMENT, "header.total_bytes: must be at least 1"},
        {{Header(101)},
         grpc::StatusCode::RESOURCE_EXHAUSTED,
         "header.total_bytes: 101 bytes, over the upload limit of 100"},
        {{Header(4), Data("ab"), Header(4)},
         grpc::StatusCode::INVALID_ARGUMENT,
         "chunks[2]: a second header"},
        {{Header(4), Data("abc"), Data("de")},
         grpc::StatusCode::INVALID_ARGUMENT,
         "chunks[2]: more bytes than header.total_bytes announced"},
    };
    for (const Case& c : cases) {
        UploadAssembler upload(100);
        grpc::Status status;
        for (const v1::SceneChunk& message : c.messages) {
            status = upload.Add(message);
            if (!status.ok()) break;
        }
        EXPECT_EQ(status.error_code(), c.code) << c.message;
        EXPECT_EQ(status.error_message(), c.message);
    }
    EXPECT_EQ(UploadAssembler(100).Finish().error_message(), "chunks: empty upload: no header");
}

}  // namespace
}  // namespace lixel
