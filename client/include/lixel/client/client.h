// The thin C++ client of lixel (DESIGN §8): one channel (several addresses are balanced
// round-robin), deadlines on every call, raised receive limits, bounded retries of calls that
// failed for transient reasons, and scenes re-uploaded when an instance answers NOT_FOUND.
#pragma once

#include <grpcpp/grpcpp.h>
#include <lixel/client/coded_frames.h>
#include <lixel/solver/result.h>
#include <lixel/v1/lixel.grpc.pb.h>

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace lixel::client {

struct ClientOptions {
    // "host:port", or "ipv4:a:p,b:q,c:r" for several instances balanced round-robin.
    std::string target = "127.0.0.1:50051";
    std::string bearer_token;         // sent as "authorization: Bearer <token>" when set
    std::string tls_root_certificate;  // PEM; set to use TLS
    std::string tls_client_certificate;  // PEM; mutual TLS
    std::string tls_client_key;          // PEM
    std::string tls_server_name;         // overrides the name checked in the server certificate
    double deadline_seconds = 120.0;     // per call
    int retries = 3;                     // extra attempts for UNAVAILABLE and NOT_FOUND
    std::size_t max_receive_bytes = 1ull << 30;
    std::size_t upload_chunk_bytes = 1ull << 20;
};

// A failed call as the server gave it: the status code's name and its message.
Error StatusError(const grpc::Status& status);

// The maps of a Render, reassembled.
struct RenderedMaps {
    v1::RenderHeader header;
    std::vector<std::vector<float>> images;  // one per header.images(), float32 row 0 at bottom
    // Coded images (RenderRequest.encoding): each one's coded header (codec, N, error bound,
    // frame, reference and keyframe ids, sizes); empty when the maps came raw.
    std::vector<codec::CodedHeader> coded;
    std::uint64_t streamed_bytes = 0;  // image bytes as they came over the wire
};

class Client {
public:
    static Result<std::unique_ptr<Client>> Connect(const ClientOptions& options);

    // Waits until the channel is ready (or the deadline passes), trying to connect at once.
    // Errors: "target", naming it, when no server answered in time.
    Result<bool> WaitForReady(double seconds);

    Result<v1::SolveResponse> Solve(const v1::SolveRequest& request);
    // Plan, Render and View carry a scene id; when an instance does not know it (evicted, or
    // another instance) the scene is uploaded again and the call retried.
    Result<v1::PlanResponse> Plan(const v1::PlanRequest& request);
    // A malformed stream (images announced past their shapes or max_receive_bytes, chunks out
    // of order or past their image) ends the call as DATA_LOSS naming the image; a coded image
    // that does not decode is an error naming images[i] and the coded-map field.
    // Coded maps (request.encoding) are decoded here. With `frames`, the frames it holds are
    // named as references (so the server may code differences from them) and this call's
    // frame is held in their place; without, every coded image is a keyframe.
    Result<RenderedMaps> Render(
        const v1::RenderRequest& request,
        const std::function<void(std::uint64_t, std::uint64_t)>& progress = {},
        CodedFrames* frames = nullptr);
    Result<v1::ViewResponse> View(const v1::ViewRequest& request);
    Result<v1::SilhouettesResponse> Silhouettes(const v1::SilhouettesRequest& request);

    // Uploads a lixel.v1.Scene, or a file's bytes in a given format; returns the scene id. The
    // content is remembered for re-uploads.
    Result<v1::UploadSceneResponse> UploadScene(const v1::Scene& scene);
    Result<v1::UploadSceneResponse> UploadContent(const v1::SceneHeader& header,
                                                  const std::string& content);

    grpc::Channel& channel() { return *channel_; }

    // Uploads `scene_id` again from the content this client uploaded it with (a session whose
    // scene was evicted: NOT_FOUND); NOT_FOUND when this client never uploaded it.
    Result<bool> UploadAgain(const std::string& scene_id);

  private:
    friend class Session;
    Client(ClientOptions options, std::shared_ptr<grpc::Channel> channel);
    void Prepare(grpc::ClientContext& context) const;
    // Runs `call` with retries; re-uploads `scene_id` on NOT_FOUND.
    grpc::Status WithRetries(const std::string& scene_id,
                             const std::function<grpc::Status(grpc::ClientContext&)>& call);
    grpc::Status Reupload(const std::string& scene_id);

    ClientOptions options_;
    std::shared_ptr<grpc::Channel> channel_;
    std::unique_ptr<v1::Shadow::Stub> stub_;
    std::mutex mutex_;
    std::map<std::string, std::pair<v1::SceneHeader, std::string>> uploaded_;
};

}  // namespace lixel::client
