// Server start-up: builder, credentials, health and reflection.
#include <grpcpp/ext/proto_server_reflection_plugin.h>
#include <grpcpp/health_check_service_interface.h>
#include <lixel/service/server.h>

#include <chrono>

#include <climits>

namespace lixel::service {

Result<std::unique_ptr<Server>> Server::Start(const ServerOptions& options) {
    if (options.service.workers < 1 || options.service.workers > 64) {
        return Error{"workers", "must be in [1, 64], got " +
                                    std::to_string(options.service.workers)};
    }
    if (options.service.queue_capacity < 1) return Error{"queue", "must be at least 1"};
    if (options.tls_certificate.empty() != options.tls_private_key.empty()) {
        return Error{"tls", "needs both a certificate and a private key"};
    }
    grpc::EnableDefaultHealthCheckService(true);
    grpc::reflection::InitProtoReflectionServerBuilderPlugin();

    if (!(options.shutdown_grace_seconds >= 0.0 && options.shutdown_grace_seconds <= 3600.0)) {
        return Error{"shutdown_grace_seconds", "must be in [0, 3600]"};
    }
    std::unique_ptr<Server> server(new Server());
    server->shutdown_grace_seconds_ = options.shutdown_grace_seconds;
    Server* raw = server.get();
    server->service_ = std::make_unique<ShadowService>(
        options.service, options.metrics_address, [raw](bool ok, const std::string&) {
            if (ok) raw->MarkServing();
        });

    std::shared_ptr<grpc::ServerCredentials> credentials;
    if (options.tls_certificate.empty()) {
        credentials = grpc::InsecureServerCredentials();
    } else {
        grpc::SslServerCredentialsOptions ssl(
            options.tls_client_ca.empty()
                ? GRPC_SSL_DONT_REQUEST_CLIENT_CERTIFICATE
                : GRPC_SSL_REQUEST_AND_REQUIRE_CLIENT_CERTIFICATE_AND_VERIFY);
        ssl.pem_root_certs = options.tls_client_ca;
        ssl.pem_key_cert_pairs.push_back({options.tls_private_key, options.tls_certificate});
        credentials = grpc::SslServerCredentials(ssl);
    }

    grpc::ServerBuilder builder;
    builder.AddListeningPort(options.address, credentials, &server->port_);
    builder.RegisterService(server->service_.get());
    builder.SetMaxReceiveMessageSize(static_cast<int>(
        std::min<std::size_t>(options.max_receive_bytes, INT_MAX)));
    builder.SetMaxSendMessageSize(static_cast<int>(
        std::min<std::uint64_t>(options.service.max_response_bytes, INT_MAX)));
    std::unique_ptr<grpc::Server> started = builder.BuildAndStart();
    if (started == nullptr || server->port_ == 0) {
        return Error{"address", "cannot listen on " + options.address};
    }
    // Workers may already be calling MarkServing (TSan found the unguarded store racing it).
    // NOT_SERVING until a worker reports a working GL context (which may have happened already).
    {
        std::lock_guard lock(server->health_mutex_);
        server->server_ = std::move(started);
        server->server_->GetHealthCheckService()->SetServingStatus(
            server->service_->gl_ready());
    }
    return server;
}

void Server::MarkServing() {
    std::lock_guard lock(health_mutex_);
    if (server_ != nullptr && !shut_down_) {
        server_->GetHealthCheckService()->SetServingStatus(true);
    }
}

Server::~Server() { Shutdown(); }

void Server::Wait() {
    grpc::Server* server = nullptr;
    {
        std::lock_guard lock(health_mutex_);
        server = server_.get();
    }
    if (server != nullptr) server->Wait();
}

void Server::Shutdown() {
    std::call_once(shutdown_once_, [this] {
        grpc::Server* server = nullptr;
        {
            std::lock_guard lock(health_mutex_);
            shut_down_ = true;
            server = server_.get();
        }
        if (server != nullptr) {
            // After the grace period gRPC cancels the calls still running; jobs see the
            // cancellation at their next check and end (jobs.h).
            server->Shutdown(std::chrono::system_clock::now() +
                             std::chrono::milliseconds(
                                 static_cast<long>(shutdown_grace_seconds_ * 1000.0)));
            server->Wait();
        }
        service_.reset();
    });
}

}  // namespace lixel::service
