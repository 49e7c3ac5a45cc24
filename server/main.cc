// lixel_server: flags only (DESIGN §1). Starts the Shadow service on an address, with its worker
// pool, limits, optional TLS, bearer or per-client tokens, and the Prometheus endpoint.
#include <lixel/render/context.h>
#include <lixel/service/access.h>
#include <lixel/service/server.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <string_view>
#include <thread>

namespace {

lixel::service::Server* running = nullptr;

void Stop(int) {
    // Shutdown from a fresh thread: it blocks until calls drain.
    if (running != nullptr) std::thread([] { running->Shutdown(); }).detach();
}

std::string ReadFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        std::fprintf(stderr, "lixel_server: cannot read %s\n", path.c_str());
        std::exit(2);
    }
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

void Usage() {
    std::fprintf(stderr,
                 "usage: lixel_server [--address=127.0.0.1:50051] [--metrics=ADDRESS]\n"
                 "  [--instance=NAME] [--workers=2] [--queue=64] [--gl=egl|osmesa]\n"
                 "  [--max_upload_mb=256] [--cache_mb=1024] [--memory_cap_mb=2048]\n"
                 "  [--max_response_mb=1024] [--max_calls_per_client=0]\n"
                 "  [--max_inflight_mb_per_client=0] [--token=SECRET | --token_file=PATH]\n"
                 "  [--clients_file=PATH (lines \"<name> <token>\": one token per client)]\n"
                 "  [--tls_cert=PEM --tls_key=PEM [--tls_client_ca=PEM]]\n");
}

}  // namespace

int main(int argc, char** argv) {
    lixel::service::ServerOptions options;
    options.service.instance.clear();
    for (int i = 1; i < argc; ++i) {
        const std::string_view arg = argv[i];
        const auto eq = arg.find('=');
        const std::string key(arg.substr(0, eq));
        const std::string value(eq == std::string_view::npos ? "" : arg.substr(eq + 1));
        auto number = [&]() -> unsigned long long {
            char* end = nullptr;
            const unsigned long long n = std::strtoull(value.c_str(), &end, 10);
            if (value.empty() || *end != '\0') {
                std::fprintf(stderr, "lixel_server: %s needs a number, got '%s'\n", key.c_str(),
                             value.c_str());
                std::exit(2);
            }
            return n;
        };
        if (key == "--address") options.address = value;
        else if (key == "--metrics") options.metrics_address = value;
        else if (key == "--instance") options.service.instance = value;
        else if (key == "--workers") options.service.workers = static_cast<int>(number());
        else if (key == "--queue") options.service.queue_capacity = number();
        else if (key == "--max_upload_mb") options.service.max_upload_bytes = number() << 20;
        else if (key == "--cache_mb") options.service.scene_cache_bytes = number() << 20;
        else if (key == "--memory_cap_mb") options.service.memory_cap_bytes = number() << 20;
        else if (key == "--max_response_mb") options.service.max_response_bytes = number() << 20;
        else if (key == "--max_calls_per_client") {
            options.service.max_calls_per_client = number();
        } else if (key == "--max_inflight_mb_per_client") {
            options.service.max_bytes_in_flight_per_client = number() << 20;
        } else if (key == "--token") options.service.bearer_token = value;
        else if (key == "--token_file") {
            options.service.bearer_token = ReadFile(value);
            while (!options.service.bearer_token.empty() &&
                   std::isspace(static_cast<unsigned char>(options.service.bearer_token.back()))) {
                options.service.bearer_token.pop_back();
            }
        }
        else if (key == "--clients_file") {
            auto tokens = lixel::service::ParseClientTokens(ReadFile(value));
            if (!tokens) {
                std::fprintf(stderr, "lixel_server: %s: %s\n", value.c_str(),
                             tokens.error().Message().c_str());
                return 2;
            }
            options.service.client_tokens = std::move(*tokens);
        }
        else if (key == "--tls_cert") options.tls_certificate = ReadFile(value);
        else if (key == "--tls_key") options.tls_private_key = ReadFile(value);
        else if (key == "--tls_client_ca") options.tls_client_ca = ReadFile(value);
        else if (key == "--gl") {
            auto backend = lixel::render::ParseBackend(value, "--gl");
            if (!backend) {
                std::fprintf(stderr, "lixel_server: %s\n", backend.error().Message().c_str());
                return 2;
            }
            options.service.gl.backend = *backend;
        } else {
            Usage();
            return arg == "--help" ? 0 : 2;
        }
    }
    if (options.service.instance.empty()) options.service.instance = "lixel@" + options.address;

    auto server = lixel::service::Server::Start(options);
    if (!server) {
        std::fprintf(stderr, "lixel_server: %s\n", server.error().Message().c_str());
        return 1;
    }
    running = server->get();
    std::signal(SIGINT, Stop);
    std::signal(SIGTERM, Stop);
    std::fprintf(stderr, "lixel_server: %s listening on port %d%s%s\n",
                 options.service.instance.c_str(), (*server)->port(),
                 options.metrics_address.empty() ? "" : ", metrics on ",
                 options.metrics_address.c_str());
    std::printf("%d\n", (*server)->port());  // the chosen port, for scripts that pass port 0
    std::fflush(stdout);
    (*server)->Wait();
    return 0;
}
