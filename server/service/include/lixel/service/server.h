// A running lixel server: the Shadow service, standard health checking (SERVING once a worker
// has a working GL context) and reflection, optional TLS and bearer token, and the metrics
// endpoint. server/main.cc and the tests start servers through this.
#pragma once

#include <grpcpp/grpcpp.h>
#include <lixel/service/shadow_service.h>
#include <lixel/solver/result.h>

#include <memory>
#include <mutex>
#include <string>

namespace lixel::service {

struct ServerOptions {
    std::string address = "127.0.0.1:50051";  // port 0 picks a free one
    std::string metrics_address;               // "127.0.0.1:9464"; empty: not exposed
    ServiceOptions service;
    // TLS: PEM strings. With a client CA set, clients must present certificates it signed.
    std::string tls_certificate;
    std::string tls_private_key;
    std::string tls_client_ca;
    std::size_t max_receive_bytes = 64ull << 20;  // one request message
    // Shutdown lets calls in flight end for this long, then cancels those still running.
    double shutdown_grace_seconds = 10.0;
};

class Server {
public:
    static Result<std::unique_ptr<Server>> Start(const ServerOptions& options);
    ~Server();

    int port() const noexcept { return port_; }
    ShadowService& service() noexcept { return *service_; }
    // Blocks until Shutdown.
    void Wait();
    // Stops taking calls, lets those in flight end for shutdown_grace_seconds and cancels the
    // rest, then stops the workers. Safe from any thread
    // and more than once (later calls wait for the first); the gRPC server object itself lives
    // until ~Server, so a thread still returning from Wait() never meets a freed one.
    void Shutdown();

private:
    Server() = default;
    void MarkServing();

    std::mutex health_mutex_;  // guards server_'s health status against workers' MarkServing
    std::once_flag shutdown_once_;
    bool shut_down_ = false;  // under health_mutex_
    std::unique_ptr<ShadowService> service_;
    std::unique_ptr<grpc::Server> server_;  // set once in Start, before any Wait or Shutdown
    int port_ = 0;
    double shutdown_grace_seconds_ = 10.0;
};

}  // namespace lixel::service
