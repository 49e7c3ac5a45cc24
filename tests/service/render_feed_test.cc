// render_feed.h: Render's streaming hand-off between the GPU worker and the call's writer.
#include <grpc/grpc.h>
#include <grpcpp/create_channel.h>
#include <grpcpp/security/credentials.h>
#include <grpcpp/support/channel_arguments.h>
#include <gtest/gtest.h>
#include <lixel/service/render_feed.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <thread>
#include <vector>

#include "service_fixture.h"

namespace lixel::service {
namespace {

render::FloatImage Ramp(int width, int height, float start) {
    render::FloatImage image{width, height, 1, {}};
    for (int i = 0; i < width * height; ++i) image.pixels.push_back(start + static_cast<float>(i));
    return image;
}

// A writer on its own thread, as gRPC's: each wake or finished write takes the next message.
class Writer {
  public:
    explicit Writer(std::uint64_t chunk_bytes)
        : feed(chunk_bytes, [this] { woken++; }) {}

    // Takes messages until the feed is idle or finished; true once finished.
    bool Drain() {
        v1::RenderChunk m;
        grpc::Status s;
        for (;;) {
            switch (feed.Next(&m, &s)) {
                case RenderFeed::Step::kWrite:
                    messages.push_back(m);
                    continue;
                case RenderFeed::Step::kIdle:
                    return false;
                case RenderFeed::Step::kFinish:
                    status = s;
                    return true;
            }
        }
    }

    RenderFeed feed;
    std::atomic<int> woken{0};
    std::vector<v1::RenderChunk> messages;
    grpc::Status status;
};

TEST(RenderFeed, HeaderThenEachImageInChunksInOrder) {
    Writer w(1000);
    v1::RenderChunk header;
    header.mutable_header()->add_images()->set_bytes(4 * 600);
    ASSERT_TRUE(w.feed.PutHeader(header));
    EXPECT_EQ(w.woken, 1);  // the writer was idle
    ASSERT_TRUE(w.feed.PutImage(0, Ramp(20, 30, 0.0f)));
    EXPECT_EQ(w.woken, 1);  // not idle: it has not drained yet
    EXPECT_FALSE(w.Drain());
    ASSERT_EQ(w.messages.size(), 1u + 3u);  // 2400 bytes in chunks of 1000
    EXPECT_TRUE(w.messages[0].has_header());
    std::vector<float> got(600);
    for (std::size_t i = 1; i < w.messages.size(); ++i) {
        const v1::MapChunk& c = w.messages[i].chunk();
        EXPECT_EQ(c.image_index(), 0u);
        EXPECT_EQ(c.offset(), 1000u * (i - 1));
        std::memcpy(reinterpret_cast<char*>(got.data()) + c.offset(), c.data().data(),
                    c.data().size());
    }
    EXPECT_EQ(got, Ramp(20, 30, 0.0f).pixels);
    w.feed.Finish(grpc::Status::OK);
    EXPECT_EQ(w.woken, 2);
    EXPECT_TRUE(w.Drain());
    EXPECT_TRUE(w.status.ok());
    EXPECT_EQ(w.feed.messages(), 4u);
}

// The producer may read an image back only once the previous one is written: never two
// images on the host.
TEST(RenderFeed, NoRoomForAnImageUntilTheLastChunkOfTheOneBeforeIsTaken) {
    Writer w(400);
    ASSERT_TRUE(w.feed.PutImage(0, Ramp(10, 30, 0.0f)));  // 1200 bytes: 3 chunks
    std::atomic<bool> room{false};
    std::thread producer([&] {
        room = w.feed.WaitForRoom({}, 60.0) == RenderFeed::Room::kRoom;
    });
    v1::RenderChunk m;
    grpc::Status s;
    for (int i = 0; i < 2; ++i) {
        ASSERT_EQ(w.feed.Next(&m, &s), RenderFeed::Step::kWrite);
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        EXPECT_FALSE(room) << "room after " << i + 1 << " of 3 chunks";
    }
    ASSERT_EQ(w.feed.Next(&m, &s), RenderFeed::Step::kWrite);  // the last chunk
    producer.join();
    EXPECT_TRUE(room);
}

TEST(RenderFeed, ClosingEndsTheProducersWaitAndRefusesMore) {
    Writer w(400);
    ASSERT_TRUE(w.feed.PutImage(0, Ramp(10, 30, 0.0f)));
    RenderFeed::Room room = RenderFeed::Room::kRoom;
    std::thread producer([&] { room = w.feed.WaitForRoom({}, 60.0); });
    std::this_thread::sleep_for(std::chrono::milliseconds(30));
    w.feed.Close();
    producer.join();
    EXPECT_EQ(room, RenderFeed::Room::kEnded);
    EXPECT_FALSE(w.feed.PutImage(1, Ramp(2, 2, 0.0f)));
    v1::RenderChunk header;
    EXPECT_FALSE(w.feed.PutHeader(header));
    // The writer still finishes the call with the job's status.
    w.feed.Finish(grpc::Status(grpc::StatusCode::CANCELLED, "gone"));
    EXPECT_TRUE(w.Drain());
    EXPECT_EQ(w.status.error_code(), grpc::StatusCode::CANCELLED);
}

TEST(RenderFeed, CancellationEndsTheWait) {
    Writer w(400);
    ASSERT_TRUE(w.feed.PutImage(0, Ramp(10, 30, 0.0f)));
    std::atomic<bool> cancelled{false};
    RenderFeed::Room room = RenderFeed::Room::kRoom;
    std::thread producer([&] { room = w.feed.WaitForRoom([&] { return cancelled.load(); }, 60.0); });
    std::this_thread::sleep_for(std::chrono::milliseconds(30));
    cancelled = true;
    producer.join();
    EXPECT_EQ(room, RenderFeed::Room::kEnded);
}

TEST(RenderFeed, AWriterThatTakesNothingStallsTheProducer) {
    Writer w(400);
    ASSERT_TRUE(w.feed.PutImage(0, Ramp(10, 30, 0.0f)));
    const auto start = std::chrono::steady_clock::now();
    EXPECT_EQ(w.feed.WaitForRoom({}, 0.1), RenderFeed::Room::kStalled);
    EXPECT_GE(std::chrono::steady_clock::now() - start, std::chrono::milliseconds(100));
}

TEST(RenderFeed, AnErrorDropsWhatWasNotWrittenAndFinishesAtOnce) {
    Writer w(400);
    v1::RenderChunk header;
    header.mutable_header();
    ASSERT_TRUE(w.feed.PutHeader(header));
    ASSERT_TRUE(w.feed.PutImage(0, Ramp(10, 30, 0.0f)));
    w.feed.Finish(grpc::Status(grpc::StatusCode::INTERNAL, "broken"));
    EXPECT_TRUE(w.Drain());
    EXPECT_TRUE(w.messages.empty());
    EXPECT_EQ(w.status.error_code(), grpc::StatusCode::INTERNAL);
}

// A 4096² map is 64 chunks of 1 MiB: each chunk is written into the message the writer reuses
// and the next image is read back into the last one's array, so a stream allocates neither a
// buffer per chunk nor an image per map (their page faults held the transfer at 0.6 of a bare
// echo; docs/performance.md).
TEST(RenderFeed, ChunksReuseTheMessagesBufferAndTheWrittenImageIsHandedBack) {
    Writer w(400);
    render::FloatImage image = Ramp(10, 25, 0.0f);  // 1000 bytes: 400, 400, 200
    const float* pixels = image.pixels.data();
    ASSERT_TRUE(w.feed.PutImage(0, std::move(image)));
    EXPECT_TRUE(w.feed.TakeSpare().empty());  // nothing written yet

    v1::RenderChunk m;
    grpc::Status s;
    ASSERT_EQ(w.feed.Next(&m, &s), RenderFeed::Step::kWrite);
    const char* buffer = m.chunk().data().data();
    ASSERT_EQ(w.feed.Next(&m, &s), RenderFeed::Step::kWrite);
    EXPECT_EQ(m.chunk().data().data(), buffer);
    EXPECT_EQ(m.chunk().offset(), 400u);
    EXPECT_TRUE(w.feed.TakeSpare().empty());  // still being written
    ASSERT_EQ(w.feed.Next(&m, &s), RenderFeed::Step::kWrite);
    EXPECT_EQ(m.chunk().data().data(), buffer);
    EXPECT_EQ(m.chunk().data().size(), 200u);
    EXPECT_EQ(std::memcmp(m.chunk().data().data(), Ramp(10, 25, 0.0f).pixels.data() + 200, 200),
              0);

    std::vector<float> spare = w.feed.TakeSpare();
    EXPECT_EQ(spare.data(), pixels);
    EXPECT_EQ(spare.size(), 250u);
    EXPECT_TRUE(w.feed.TakeSpare().empty());  // handed back once
}

// A stub whose channel grants each stream a fixed 64 KiB window: without probing the link's
// bandwidth-delay product, a client that stops reading stops the server's writes there. With
// it, on a loaded loopback the window grew past the whole of a Render's stream (5.6 MiB), which
// then ended OK before the client read past its header (3 runs in 20 with both cores busy).
std::unique_ptr<v1::Shadow::Stub> FixedWindowStub(const std::string& target) {
    grpc::ChannelArguments args;
    args.SetInt(GRPC_ARG_HTTP2_BDP_PROBE, 0);
    args.SetInt(GRPC_ARG_HTTP2_STREAM_LOOKAHEAD_BYTES, 64 << 10);
    return v1::Shadow::NewStub(
        grpc::CreateCustomChannel(target, grpc::InsecureChannelCredentials(), args));
}

// Through the server: a client that reads the header and then nothing frees the only render
// worker after stream_idle_seconds, another client's View is served meanwhile, and the stalled
// stream ends RESOURCE_EXHAUSTED naming the limit once it is read again.
TEST(RenderStreaming, AStalledReaderDoesNotHoldTheWorker) {
    ServerOptions options = testing::SmallServerOptions("test-stall");
    options.service.workers = 1;
    options.service.chunk_bytes = 64 << 10;
    options.service.stream_idle_seconds = 0.3;
    auto server = testing::StartServer(options);
    auto client = testing::Connect(testing::Target(*server));
    auto uploaded = client->UploadScene(testing::SmallScene());
    ASSERT_TRUE(uploaded.ok()) << uploaded.error().Message();

    auto stub = FixedWindowStub(testing::Target(*server));
    grpc::ClientContext held;
    testing::WithDeadline(held);
    auto reader = stub->Render(&held, testing::BigRender(uploaded->scene_id()));
    v1::RenderChunk chunk;
    ASSERT_TRUE(reader->Read(&chunk));
    ASSERT_TRUE(chunk.has_header());

    v1::ViewRequest view;
    view.mutable_plan()->set_scene_id(uploaded->scene_id());
    const auto start = std::chrono::steady_clock::now();
    auto served = client->View(view);
    ASSERT_TRUE(served.ok()) << served.error().Message();
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(30));

    while (reader->Read(&chunk)) {
    }
    const grpc::Status status = reader->Finish();
    EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
    EXPECT_NE(status.error_message().find("stream_idle_seconds = 0.3"), std::string::npos)
        << status.error_message();
}

}  // namespace
}  // namespace lixel::service
