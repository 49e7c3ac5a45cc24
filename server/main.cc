// lixel_server: flags only (DESIGN §1). Starts the Shadow service on an address, with its worker
// pool, limits, optional TLS, bearer or per-client tokens, and the Prometheus endpoint.
#include <absl/flags/flag.h>
#include <absl/flags/parse.h>
#include <absl/flags/reflection.h>
#include <lixel/render/context.h>
#include <lixel/service/access.h>
#include <lixel/command_line/flag_scan.h>
#include <lixel/service/server.h>

#include <pthread.h>

#include <cctype>
#include <chrono>
#include <cmath>
#include <csignal>
#include <future>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <thread>

namespace {

// Flag defaults are the options' own, so the two cannot drift apart.
const lixel::service::ServerOptions& Defaults() {
    static const lixel::service::ServerOptions defaults;
    return defaults;
}

std::uint64_t Mib(std::uint64_t bytes) { return bytes >> 20; }

}  // namespace

ABSL_FLAG(std::string, address, Defaults().address,
          "host:port to listen on; port 0 picks a free one and prints it on stdout");
ABSL_FLAG(std::string, metrics, "", "host:port of the Prometheus endpoint (/metrics); empty: none");
ABSL_FLAG(std::string, instance, "", "name in every reply; empty: lixel@<address>");
ABSL_FLAG(int, workers, Defaults().service.workers,
          "render workers, each with its own GL context, [1, 64]");
ABSL_FLAG(std::uint64_t, queue, Defaults().service.queue_capacity,
          "tasks waiting beyond which calls get RESOURCE_EXHAUSTED, [1, 1048576]");
ABSL_FLAG(std::string, gl, lixel::render::BackendName(Defaults().service.gl.backend),
          "GL backend of the render workers: egl or osmesa");
ABSL_FLAG(std::uint64_t, max_upload_mb, Mib(Defaults().service.max_upload_bytes),
          "MiB one scene upload may announce, [1, 1048576]");
ABSL_FLAG(std::uint64_t, max_upload_vertices, Defaults().service.max_upload_vertices,
          "vertices one upload may decode into, all meshes after triangulation and instancing, "
          "[1, 2^32]");
ABSL_FLAG(std::uint64_t, max_upload_triangles, Defaults().service.max_upload_triangles,
          "triangles one upload may decode into, all meshes after triangulation and instancing, "
          "[1, 2^32]");
ABSL_FLAG(std::uint64_t, max_upload_json_values, Defaults().service.max_upload_json_values,
          "JSON values of one uploaded glTF document, [1, 2^32]");
ABSL_FLAG(std::uint64_t, max_upload_inflight_mb, Mib(Defaults().service.max_upload_bytes_in_flight),
          "MiB all upload streams together may hold at once, from each header on until decoded, "
          "[1, 1048576]");
ABSL_FLAG(double, upload_idle_seconds, Defaults().service.upload_idle_seconds,
          "seconds an upload stream may send nothing before it is ended, (0, 3600]");
ABSL_FLAG(double, stream_idle_seconds, Defaults().service.stream_idle_seconds,
          "seconds a Render stream's client may take nothing before the stream is ended, "
          "(0, 3600]");
ABSL_FLAG(bool, log_requests, Defaults().service.log_requests,
          "one line per call on stderr: request id, RPC, peer, client, scene, status, time");
ABSL_FLAG(std::uint64_t, coded_reference_mb, Mib(Defaults().service.coded_reference_bytes),
          "MiB of coded frames kept so later Renders may code differences from them, least "
          "recently used evicted first, [0, 1048576]");
ABSL_FLAG(std::uint64_t, session_waiting_mb, Mib(Defaults().service.session_waiting_bytes),
          "MiB a session's frames received and not started may hold together before the oldest "
          "are skipped, [1, 1048576]");
ABSL_FLAG(std::uint64_t, cache_mb, Mib(Defaults().service.scene_cache_bytes),
          "MiB of decoded scenes kept, least recently used evicted first, [1, 1048576]");
ABSL_FLAG(std::uint64_t, memory_cap_mb, Mib(Defaults().service.memory_cap_bytes),
          "MiB of maps one request may need (width x height x 4 x passes), [1, 1048576]");
ABSL_FLAG(std::uint64_t, max_plan_objects, Defaults().service.max_plan_objects,
          "objects one plan may hold (a request's objects, an uploaded scene's meshes), "
          "[0, 2^32]; 0: memory_cap_mb at 8 KiB an object");
ABSL_FLAG(std::uint64_t, max_response_mb, Mib(Defaults().service.max_response_bytes),
          "MiB one Render or View may return, [1, 1048576]");
ABSL_FLAG(std::uint64_t, max_calls_per_client, Defaults().service.max_calls_per_client,
          "calls one client may have in flight at once, [0, 1048576]; 0: no limit");
ABSL_FLAG(std::uint64_t, max_inflight_mb_per_client,
          Mib(Defaults().service.max_bytes_in_flight_per_client),
          "MiB of requests and responses one client's calls may hold, [0, 1048576]; 0: no limit");
ABSL_FLAG(double, shutdown_grace_seconds, Defaults().shutdown_grace_seconds,
          "seconds calls in flight may take to end at shutdown before they are cancelled, "
          "(0, 3600]");
ABSL_FLAG(std::string, token, "",
          "require \"authorization: Bearer <token>\" on every call, one token shared by its "
          "holders");
ABSL_FLAG(std::string, token_file, "", "as --token, the token read from this file");
ABSL_FLAG(std::string, clients_file, "",
          "one token per client: lines \"<name> <token>\"; the name is the client's identity for "
          "the per-client limits");
ABSL_FLAG(std::string, tls_cert, "", "serve TLS with this PEM certificate (with --tls_key)");
ABSL_FLAG(std::string, tls_key, "", "PEM private key of --tls_cert");
ABSL_FLAG(std::string, tls_client_ca, "",
          "PEM CA; clients must present certificates it signed (with --tls_cert)");

namespace {

// SIGINT and SIGTERM are blocked in every thread and taken by one thread with sigwait, so the
// shutdown runs in ordinary code, never in a signal handler. The first signal shuts down (calls
// in flight get --shutdown_grace_seconds, then are cancelled); if the process is still alive
// 5 s after that, or a second signal comes, it exits at once: SIGTERM always ends the process.
void BlockStopSignals(sigset_t* set) {
    sigemptyset(set);
    sigaddset(set, SIGINT);
    sigaddset(set, SIGTERM);
    pthread_sigmask(SIG_BLOCK, set, nullptr);
}

[[noreturn]] void ExitNow(const char* why) {
    std::fprintf(stderr, "lixel_server: %s; exiting now\n", why);
    std::fflush(stderr);
    std::_Exit(1);
}

void TakeStopSignals(sigset_t set, lixel::service::Server* server, double grace_seconds,
                     std::promise<void>* stopped) {
    std::thread([set, server, grace_seconds, stopped] {
        int signal = 0;
        sigwait(&set, &signal);
        std::fprintf(stderr, "lixel_server: %s: shutting down\n",
                     signal == SIGTERM ? "SIGTERM" : "SIGINT");
        std::thread([server, stopped] {
            server->Shutdown();
            stopped->set_value();
        }).detach();
        std::thread([grace_seconds] {
            std::this_thread::sleep_for(std::chrono::duration<double>(grace_seconds + 5.0));
            ExitNow("shutdown did not finish in time");
        }).detach();
        sigwait(&set, &signal);
        ExitNow("a second stop signal");
    }).detach();
}

[[noreturn]] void Refuse(const std::string& message) {
    std::fprintf(stderr, "lixel_server: %s\n", message.c_str());
    std::exit(2);
}

std::string ReadFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) Refuse("cannot read " + path);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

// Numeric flags and the values they accept; each flag's help says the same, for --help. MiB flags
// stop at 2^20 so that << 20 stays inside 64 bits; a count of 2^32 already means tens of GiB
// decoded.
struct Bounds {
    std::string_view flag;
    double lo;
    double hi;
    bool lo_open;  // (lo, hi] rather than [lo, hi]
};
constexpr double kMaxMib = 1 << 20;
constexpr double kMaxCount = 4294967296.0;  // 2^32
constexpr Bounds kBounds[] = {
    {"workers", 1, 64, false},
    {"queue", 1, 1 << 20, false},
    {"max_upload_mb", 1, kMaxMib, false},
    {"max_upload_vertices", 1, kMaxCount, false},
    {"max_upload_triangles", 1, kMaxCount, false},
    {"max_upload_json_values", 1, kMaxCount, false},
    {"max_upload_inflight_mb", 1, kMaxMib, false},
    {"upload_idle_seconds", 0, 3600, true},
    {"stream_idle_seconds", 0, 3600, true},
    {"cache_mb", 1, kMaxMib, false},
    {"coded_reference_mb", 0, kMaxMib, false},
    {"session_waiting_mb", 1, kMaxMib, false},
    {"memory_cap_mb", 1, kMaxMib, false},
    {"max_plan_objects", 0, kMaxCount, false},
    {"max_response_mb", 1, kMaxMib, false},
    {"max_calls_per_client", 0, 1 << 20, false},
    {"max_inflight_mb_per_client", 0, kMaxMib, false},
    {"shutdown_grace_seconds", 0, 3600, true},
};

std::string Number(double v) {
    char text[32];
    std::snprintf(text, sizeof text, v == std::floor(v) && std::fabs(v) < 1e15 ? "%.0f" : "%g", v);
    return text;
}

std::string RangeText(const Bounds& b) {
    return std::string(b.lo_open ? "(" : "[") + Number(b.lo) + ", " + Number(b.hi) + "]";
}

const Bounds* BoundsOf(std::string_view flag) {
    for (const Bounds& b : kBounds) {
        if (b.flag == flag) return &b;
    }
    return nullptr;
}

// A numeric flag's value as a double (exact for every integer up to 2^53, and no bound is
// larger); NaN fails every comparison, so it is out of every range.
std::optional<double> ValueOf(const absl::CommandLineFlag& flag) {
    if (auto v = flag.TryGet<int>()) return static_cast<double>(*v);
    if (auto v = flag.TryGet<std::uint64_t>()) return static_cast<double>(*v);
    if (auto v = flag.TryGet<double>()) return *v;
    return std::nullopt;
}

// This file's flags, as against absl's own and any a linked library defines.
bool Ours(const absl::CommandLineFlag& flag) {
    return std::string_view(__FILE__).ends_with(flag.Filename());
}

// Reads argv as absl::ParseCommandLine will, before it does, and returns the names given. absl
// refuses an unknown flag or a bad value by exiting 1, the code of a failed run; an operator's
// mistake exits 2 here instead, naming the flag and what it accepts. absl would also take flags
// from --flagfile and the environment (--fromenv); the server's inputs are its command line
// only, so what was given is known exactly (a --token_file that came from elsewhere would be
// skipped, and the server would run without a token).
std::set<std::string> ScanArguments(int argc, char** argv) {
    const lixel::command_line::ScanRules rules{
        Ours,
        [](const std::string& name) {
            return lixel::Error{"--" + name, "is not a flag of lixel_server (--help lists them)"};
        },
        [](const absl::CommandLineFlag& flag, const std::string& value, const std::string& error) {
            const Bounds* bounds = BoundsOf(std::string(flag.Name()));
            return lixel::Error{"--" + std::string(flag.Name()) + "=" + value,
                                error + (bounds != nullptr ? "; valid: " + RangeText(*bounds) : "")};
        }};
    std::set<std::string> given;
    for (int i = 1; i < argc; ++i) {
        std::string_view arg = argv[i];
        if (arg.size() < 2 || arg[0] != '-' || arg == "--") {
            Refuse("unexpected argument '" + std::string(arg) +
                   "': lixel_server takes flags only (--help lists them)");
        }
        auto scanned = lixel::command_line::ScanFlag(argc, argv, i, rules);
        if (!scanned) Refuse(scanned.error().Message());
        // Null: absl's --help and friends, handled by absl.
        if (scanned->flag != nullptr) given.insert(std::string(scanned->flag->Name()));
    }
    return given;
}

void CheckBounds() {
    for (const Bounds& b : kBounds) {
        const absl::CommandLineFlag* flag =
            absl::FindCommandLineFlag({b.flag.data(), b.flag.size()});
        const std::optional<double> v = flag == nullptr ? std::nullopt : ValueOf(*flag);
        if (!v) Refuse("--" + std::string(b.flag) + ": not a numeric flag");  // a broken table
        const bool above_lo = b.lo_open ? *v > b.lo : *v >= b.lo;
        if (!(above_lo && *v <= b.hi)) {
            Refuse("--" + std::string(b.flag) + "=" + flag->CurrentValue() +
                   ": out of range, valid: " + RangeText(b));
        }
    }
}

std::string TrimmedEnd(std::string text) {
    while (!text.empty() && std::isspace(static_cast<unsigned char>(text.back()))) {
        text.pop_back();
    }
    return text;
}

}  // namespace

int main(int argc, char** argv) {
    // --help lists this file's flags, named from the source root ("server/main.cc").
    lixel::command_line::ListFlagsOf(__FILE__, "server/main.cc",
                                     "serves lixel.v1.Shadow; flags as --name=value "
                                     "(docs/service.md)");
    const std::set<std::string> given = ScanArguments(argc, argv);
    absl::ParseCommandLine(argc, argv);  // --help and friends print and exit here
    CheckBounds();
    if (given.contains("token") && given.contains("token_file")) {
        Refuse("--token and --token_file: give one of them");
    }

    lixel::service::ServerOptions options;
    options.address = absl::GetFlag(FLAGS_address);
    options.metrics_address = absl::GetFlag(FLAGS_metrics);
    options.service.instance = absl::GetFlag(FLAGS_instance);
    options.service.workers = absl::GetFlag(FLAGS_workers);
    options.service.queue_capacity = absl::GetFlag(FLAGS_queue);
    // Every MiB value is at most 2^20 (CheckBounds), so each shift below fits 64 bits.
    options.service.max_upload_bytes = absl::GetFlag(FLAGS_max_upload_mb) << 20;
    options.service.max_upload_vertices = absl::GetFlag(FLAGS_max_upload_vertices);
    options.service.max_upload_triangles = absl::GetFlag(FLAGS_max_upload_triangles);
    options.service.max_upload_json_values = absl::GetFlag(FLAGS_max_upload_json_values);
    options.service.max_upload_bytes_in_flight = absl::GetFlag(FLAGS_max_upload_inflight_mb) << 20;
    options.service.upload_idle_seconds = absl::GetFlag(FLAGS_upload_idle_seconds);
    options.service.stream_idle_seconds = absl::GetFlag(FLAGS_stream_idle_seconds);
    options.service.log_requests = absl::GetFlag(FLAGS_log_requests);
    options.service.scene_cache_bytes = absl::GetFlag(FLAGS_cache_mb) << 20;
    options.service.coded_reference_bytes = absl::GetFlag(FLAGS_coded_reference_mb) << 20;
    options.service.session_waiting_bytes = absl::GetFlag(FLAGS_session_waiting_mb) << 20;
    options.service.memory_cap_bytes = absl::GetFlag(FLAGS_memory_cap_mb) << 20;
    options.service.max_plan_objects = absl::GetFlag(FLAGS_max_plan_objects);
    options.service.max_response_bytes = absl::GetFlag(FLAGS_max_response_mb) << 20;
    options.service.max_calls_per_client = absl::GetFlag(FLAGS_max_calls_per_client);
    options.service.max_bytes_in_flight_per_client =
        absl::GetFlag(FLAGS_max_inflight_mb_per_client) << 20;
    options.shutdown_grace_seconds = absl::GetFlag(FLAGS_shutdown_grace_seconds);
    options.service.bearer_token = absl::GetFlag(FLAGS_token);
    // A file flag given with an empty path is a mistake (an unset variable in a script), never a
    // request for no token: it is read, and refused as unreadable.
    if (given.contains("token_file")) {
        options.service.bearer_token = TrimmedEnd(ReadFile(absl::GetFlag(FLAGS_token_file)));
    }
    if (given.contains("clients_file")) {
        const std::string path = absl::GetFlag(FLAGS_clients_file);
        auto tokens = lixel::service::ParseClientTokens(ReadFile(path));
        if (!tokens) Refuse(path + ": " + tokens.error().Message());
        options.service.client_tokens = std::move(*tokens);
    }
    if (given.contains("tls_cert")) {
        options.tls_certificate = ReadFile(absl::GetFlag(FLAGS_tls_cert));
    }
    if (given.contains("tls_key")) options.tls_private_key = ReadFile(absl::GetFlag(FLAGS_tls_key));
    if (given.contains("tls_client_ca")) {
        options.tls_client_ca = ReadFile(absl::GetFlag(FLAGS_tls_client_ca));
    }
    auto backend = lixel::render::ParseBackend(absl::GetFlag(FLAGS_gl), "--gl");
    if (!backend) Refuse(backend.error().Message());
    options.service.gl.backend = *backend;
    if (options.service.instance.empty()) options.service.instance = "lixel@" + options.address;

    sigset_t stop_signals;
    BlockStopSignals(&stop_signals);  // before any thread starts, so that all inherit the mask
    auto server = lixel::service::Server::Start(options);
    if (!server) {
        std::fprintf(stderr, "lixel_server: %s\n", server.error().Message().c_str());
        return 1;
    }
    std::promise<void> stopped;
    TakeStopSignals(stop_signals, server->get(), options.shutdown_grace_seconds, &stopped);
    std::fprintf(stderr, "lixel_server: %s listening on port %d%s%s\n",
                 options.service.instance.c_str(), (*server)->port(),
                 options.metrics_address.empty() ? "" : ", metrics on ",
                 options.metrics_address.c_str());
    std::printf("%d\n", (*server)->port());  // the chosen port, for scripts that pass port 0
    std::fflush(stdout);
    (*server)->Wait();
    stopped.get_future().wait();  // the workers are stopped too
    return 0;
}
