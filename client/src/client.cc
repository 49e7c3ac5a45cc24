// The thin client: channel, deadlines, retries, re-uploads.
#include <lixel/client/client.h>

#include <chrono>
#include <climits>
#include <cstring>
#include <optional>
#include <thread>

#include "map_stream.h"

namespace lixel::client {

namespace {

// Uploads tried per NOT_FOUND before the call is retried (instances behind one channel).
constexpr int kReuploadAttempts = 8;

bool Transient(const grpc::Status& s) {
    return s.error_code() == grpc::StatusCode::UNAVAILABLE;
}

const char* CodeName(grpc::StatusCode code) {
    static const char* const kNames[] = {
        "OK",           "CANCELLED",          "UNKNOWN",        "INVALID_ARGUMENT",
        "DEADLINE_EXCEEDED", "NOT_FOUND",     "ALREADY_EXISTS", "PERMISSION_DENIED",
        "RESOURCE_EXHAUSTED", "FAILED_PRECONDITION", "ABORTED",  "OUT_OF_RANGE",
        "UNIMPLEMENTED", "INTERNAL",          "UNAVAILABLE",    "DATA_LOSS",
        "UNAUTHENTICATED"};
    const int i = static_cast<int>(code);
    return i >= 0 && i < 17 ? kNames[i] : "UNKNOWN";
}

}  // namespace

Error StatusError(const grpc::Status& status) {
    return Error{CodeName(status.error_code()), status.error_message()};
}

Result<std::unique_ptr<Client>> Client::Connect(const ClientOptions& options) {
    if (options.target.empty()) return Error{"target", "is empty"};
    std::shared_ptr<grpc::ChannelCredentials> credentials;
    if (options.tls_root_certificate.empty()) {
        credentials = grpc::InsecureChannelCredentials();
    } else {
        grpc::SslCredentialsOptions ssl;
        ssl.pem_root_certs = options.tls_root_certificate;
        ssl.pem_cert_chain = options.tls_client_certificate;
        ssl.pem_private_key = options.tls_client_key;
        credentials = grpc::SslCredentials(ssl);
    }
    grpc::ChannelArguments args;
    args.SetMaxReceiveMessageSize(
        static_cast<int>(std::min<std::size_t>(options.max_receive_bytes, INT_MAX)));
    args.SetMaxSendMessageSize(64 << 20);
    // Several addresses: spread calls over them (DESIGN §8, stateless instances).
    args.SetServiceConfigJSON(R"({"loadBalancingConfig": [{"round_robin": {}}]})");
    if (!options.tls_server_name.empty()) {
        args.SetSslTargetNameOverride(options.tls_server_name);
    }
    auto channel = grpc::CreateCustomChannel(options.target, credentials, args);
    if (channel == nullptr) return Error{"target", "cannot create a channel to " + options.target};
    return std::unique_ptr<Client>(new Client(options, std::move(channel)));
}

Client::Client(ClientOptions options, std::shared_ptr<grpc::Channel> channel)
    : options_(std::move(options)),
      channel_(std::move(channel)),
      stub_(v1::Shadow::NewStub(channel_)) {}

Result<bool> Client::WaitForReady(double seconds) {
    // Connect now, not after the backoff earlier failed attempts grew: a server that has just
    // come back is found by this wait, not by a later one.
    grpc::experimental::ChannelResetConnectionBackoff(channel_.get());
    const auto deadline = std::chrono::system_clock::now() +
                          std::chrono::milliseconds(static_cast<long>(seconds * 1000));
    if (!channel_->WaitForConnected(deadline)) {
        return Error{"target", "no server answered at " + options_.target + " within " +
                                   std::to_string(seconds) + " s"};
    }
    return true;
}

void Client::Prepare(grpc::ClientContext& context) const {
    context.set_deadline(std::chrono::system_clock::now() +
                         std::chrono::milliseconds(
                             static_cast<long>(options_.deadline_seconds * 1000)));
    context.set_wait_for_ready(true);
    if (!options_.bearer_token.empty()) {
        context.AddMetadata("authorization", "Bearer " + options_.bearer_token);
    }
}

grpc::Status Client::WithRetries(const std::string& scene_id,
                                 const std::function<grpc::Status(grpc::ClientContext&)>& call) {
    grpc::Status status;
    for (int attempt = 0; attempt <= options_.retries; ++attempt) {
        grpc::ClientContext context;
        Prepare(context);
        status = call(context);
        if (status.ok()) return status;
        if (status.error_code() == grpc::StatusCode::NOT_FOUND && !scene_id.empty()) {
            // This instance lost or never had the scene: give it the scene and try again.
            const grpc::Status uploaded = Reupload(scene_id);
            if (!uploaded.ok()) return uploaded;
            continue;
        }
        if (!Transient(status)) return status;
        std::this_thread::sleep_for(std::chrono::milliseconds(50 << attempt));
    }
    return status;
}

Result<bool> Client::UploadAgain(const std::string& scene_id) {
    const grpc::Status s = Reupload(scene_id);
    if (!s.ok()) return StatusError(s);
    return true;
}

grpc::Status Client::Reupload(const std::string& scene_id) {
    v1::SceneHeader header;
    std::string content;
    {
        std::lock_guard lock(mutex_);
        const auto it = uploaded_.find(scene_id);
        if (it == uploaded_.end()) {
            return grpc::Status(grpc::StatusCode::NOT_FOUND,
                                "scene_id: " + scene_id + " is unknown to the server and was "
                                "not uploaded by this client");
        }
        header = it->second.first;
        content = it->second.second;
    }
    // With several instances behind round_robin the upload may land on one that has the scene
    // already; go on until one did not (the instance that answered NOT_FOUND, or another that
    // would), so every instance ends up holding it.
    for (int attempt = 0; attempt < kReuploadAttempts; ++attempt) {
        auto uploaded = UploadContent(header, content);
        if (!uploaded) {
            return grpc::Status(grpc::StatusCode::UNAVAILABLE, uploaded.error().Message());
        }
        if (!uploaded->already_present()) break;
    }
    return grpc::Status::OK;
}

Result<v1::UploadSceneResponse> Client::UploadScene(const v1::Scene& scene) {
    v1::SceneHeader header;
    header.set_format(v1::SCENE_FORMAT_LIXEL);
    std::string content;
    scene.SerializeToString(&content);
    return UploadContent(header, content);
}

Result<v1::UploadSceneResponse> Client::UploadContent(const v1::SceneHeader& given,
                                                      const std::string& content) {
    v1::SceneHeader header = given;
    header.set_total_bytes(content.size());
    v1::UploadSceneResponse response;
    grpc::Status status;
    for (int attempt = 0; attempt <= options_.retries; ++attempt) {
        grpc::ClientContext context;
        Prepare(context);
        auto writer = stub_->UploadScene(&context, &response);
        v1::SceneChunk chunk;
        *chunk.mutable_header() = header;
        bool sent = writer->Write(chunk);
        for (std::size_t offset = 0; sent && offset < content.size();
             offset += options_.upload_chunk_bytes) {
            v1::SceneChunk data;
            data.set_data(content.substr(offset, options_.upload_chunk_bytes));
            sent = writer->Write(data);
        }
        writer->WritesDone();
        status = writer->Finish();
        if (status.ok() || !Transient(status)) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(50 << attempt));
    }
    if (!status.ok()) return StatusError(status);
    std::lock_guard lock(mutex_);
    uploaded_[response.scene_id()] = {header, content};
    return response;
}

Result<v1::SolveResponse> Client::Solve(const v1::SolveRequest& request) {
    v1::SolveResponse response;
    const grpc::Status s = WithRetries("", [&](grpc::ClientContext& c) {
        return stub_->Solve(&c, request, &response);
    });
    if (!s.ok()) return StatusError(s);
    return response;
}

Result<v1::PlanResponse> Client::Plan(const v1::PlanRequest& request) {
    v1::PlanResponse response;
    const grpc::Status s = WithRetries(request.scene_id(), [&](grpc::ClientContext& c) {
        response.Clear();
        return stub_->Plan(&c, request, &response);
    });
    if (!s.ok()) return StatusError(s);
    return response;
}

Result<RenderedMaps> Client::Render(
    const v1::RenderRequest& request,
    const std::function<void(std::uint64_t, std::uint64_t)>& progress, CodedFrames* frames) {
    const bool coding = request.encoding().codec() != v1::MAP_CODEC_RAW;
    v1::RenderRequest sent = request;
    if (coding && frames != nullptr) frames->NameIn(sent.mutable_encoding());
    std::optional<MapStream> stream;
    const grpc::Status s = WithRetries(request.plan().scene_id(), [&](grpc::ClientContext& c) {
        stream.emplace(coding, options_.max_receive_bytes);
        auto reader = stub_->Render(&c, sent);
        v1::RenderChunk chunk;
        // What a malformed stream did (a broken or hostile server): the call ends with it.
        std::string malformed;
        while (malformed.empty() && reader->Read(&chunk)) {
            if (chunk.has_header()) {
                malformed = stream->Header(chunk.header());
            } else {
                malformed = stream->Chunk(chunk.chunk());
                if (malformed.empty() && progress) progress(stream->received(), stream->total());
            }
            if (!malformed.empty()) c.TryCancel();
        }
        const grpc::Status finished = reader->Finish();
        if (!malformed.empty()) return grpc::Status(grpc::StatusCode::DATA_LOSS, malformed);
        return finished;
    });
    if (!s.ok()) return StatusError(s);
    CodedFrames own;
    return stream->Finish(frames != nullptr ? *frames : own);
}

Result<v1::ViewResponse> Client::View(const v1::ViewRequest& request) {
    v1::ViewResponse response;
    const grpc::Status s = WithRetries(request.plan().scene_id(), [&](grpc::ClientContext& c) {
        response.Clear();
        return stub_->View(&c, request, &response);
    });
    if (!s.ok()) return StatusError(s);
    return response;
}

Result<v1::SilhouettesResponse> Client::Silhouettes(const v1::SilhouettesRequest& request) {
    v1::SilhouettesResponse response;
    const grpc::Status s = WithRetries(request.scene_id(), [&](grpc::ClientContext& c) {
        response.Clear();
        return stub_->Silhouettes(&c, request, &response);
    });
    if (!s.ok()) return StatusError(s);
    return response;
}

}  // namespace lixel::client
