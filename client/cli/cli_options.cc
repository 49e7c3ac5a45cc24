// Flag parsing and scene loading for the lixel CLI.
#include "cli_options.h"

#include <absl/flags/flag.h>
#include <absl/flags/parse.h>
#include <absl/flags/reflection.h>
#include <lixel/command_line/flag_scan.h>
#include <lixel/scene/builtin_scenes.h>
#include <lixel/scene/scene_io.h>
#include <lixel/service/proto_convert.h>

#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace {

// Flag defaults are the client's own, so the two cannot drift apart.
const lixel::client::ClientOptions& ClientDefaults() {
    static const lixel::client::ClientOptions defaults;
    return defaults;
}

constexpr double kMaxDeadlineSeconds = 86400.0;  // per call; a --full report makes many calls

}  // namespace

ABSL_FLAG(std::string, target, ClientDefaults().target,
          "host:port of the server, or ipv4:a:p,b:q,... (several instances, round-robin), or "
          "dns:///name:port");
ABSL_FLAG(std::string, token, "", "sent as \"authorization: Bearer <token>\"");
ABSL_FLAG(std::string, token_file, "", "as --token, the token read from this file");
ABSL_FLAG(std::string, tls_ca, "", "PEM root certificate; set to use TLS");
ABSL_FLAG(std::string, tls_cert, "", "PEM client certificate, for mutual TLS (with --tls_key)");
ABSL_FLAG(std::string, tls_key, "", "PEM private key of --tls_cert");
ABSL_FLAG(std::string, tls_server_name, "", "name checked in the server's certificate");
ABSL_FLAG(double, deadline, ClientDefaults().deadline_seconds,
          "seconds each call may take, (0, 86400]");
ABSL_FLAG(std::string, scene, "floor_wall",
          "built-in scene: floor_wall, table_floor, sphere_grid, thin_plates, sphere_torus, pins");
ABSL_FLAG(std::string, scene_file, "", "scene file (docs/scenes.md), instead of --scene");
ABSL_FLAG(std::uint64_t, budget, 512 * 512,
          "lixels: the plan's total for plan, render and view (at least 1); solve's per-map "
          "budget, none unless given");
ABSL_FLAG(std::uint64_t, fallback_floor, 0,
          "lixels the fallback map gets at least; 0: the server's default, 128^2");
ABSL_FLAG(bool, second_depth, false, "plan a second-depth pass");
ABSL_FLAG(bool, silhouette_map, false, "plan a silhouette-map pass");
ABSL_FLAG(bool, volumes, false, "plan silhouette shadow volumes");
ABSL_FLAG(bool, twist, false, "solve: the twist that minimises the map's area");
ABSL_FLAG(std::string, out, "",
          "output folder; default out/maps (render), out/view (view), out/report (report)");
ABSL_FLAG(bool, pfm, false, "render: write maps as PFM instead of OpenEXR");
ABSL_FLAG(std::string, method, "plane_optimal",
          "view: plane_optimal, uniform, psm, lispsm or csm");
ABSL_FLAG(int, cascades, 4, "view --method=csm: cascades, [1, 8]");
ABSL_FLAG(double, split_lambda, 0.5,
          "view --method=csm: the practical split's logarithmic weight, [0, 1]");
ABSL_FLAG(bool, stable_cascades, true,
          "view --method=csm: sphere fit and texel snapping (directional lights)");
ABSL_FLAG(std::string, filter, "depth",
          "view: depth, pcf, second_depth, silhouette_map, volumes or smooth_volumes");
ABSL_FLAG(double, smooth_epsilon, 1e-3,
          "view --filter=smooth_volumes: subdivision tolerance (paper 002), world units, > 0");
ABSL_FLAG(double, normal_offset, -1.0,
          "view --filter=smooth_volumes: contour offset along -n, world units, >= 0; "
          "default 15 epsilon (the paper's 0.15 at its epsilon 0.01)");
ABSL_FLAG(bool, evaluate, false, "view: the error against exact visibility");
ABSL_FLAG(bool, timings, false, "view: per-stage run times");
ABSL_FLAG(bool, all, false, "report: every built-in scene");
ABSL_FLAG(bool, full, false, "report: every built-in scene, method and budget");
ABSL_FLAG(bool, depth_only, false, "report: the depth-test methods only");
ABSL_FLAG(int, repeats, 5,
          "report: timed runs per row after one untimed warm-up, [1, 100]; medians, min and max "
          "are taken over them (fewer than 5 is noted in report.md)");
ABSL_FLAG(std::vector<std::string>, budgets, {},
          "report: comma-separated lixel budgets, each at least 1; default 256^2, 512^2, 1024^2");
ABSL_FLAG(int, frames, 60, "sequence, frames: frames of the camera path, [1, 100000]");
ABSL_FLAG(int, size, 512, "sequence, frames: the viewer's image side, pixels, [1, 16384]");
ABSL_FLAG(double, waste_bound, 0.25,
          "sequence: coherent plane maps keep their size while the needed rectangle fills at "
          "least 1 - this share of it, (0, 1)");
ABSL_FLAG(int, scale_steps, 4,
          "sequence: coherent plane scale rounded down to 2^(-k / this), [1, 64]");
ABSL_FLAG(double, twist_saving, 0.1,
          "sequence: coherent plane maps keep their twist unless another saves this share of "
          "lixels, [0, 1)");
ABSL_FLAG(bool, coherent, false,
          "frames: frame-coherent planning, each request carrying the previous frame's maps "
          "(FrameCoherence, server defaults)");
ABSL_FLAG(std::string, encoding, "raw",
          "render, frames: how maps travel: raw (float32), quantised (depth to N bits with a "
          "stated bound, coded) or exact (float32 bits, coded); docs/service.md, \"Coded maps\"");
ABSL_FLAG(std::uint32_t, bits, 0,
          "render, frames --encoding=quantised: N in [16, 24]; 0 chooses per map");
ABSL_FLAG(bool, check, false,
          "frames: also call View for each frame and compare the engine's mask with the server's");
ABSL_FLAG(std::int64_t, max_differing, 8,
          "frames --check: exit 1 when a frame has more pixels whose lit answer differs from "
          "View's mask, >= 0");

namespace lixel::cli {

namespace {

// This file's flags, as against absl's own and any a linked library defines.
bool Ours(const absl::CommandLineFlag& flag) {
    return std::string_view(__FILE__).ends_with(flag.Filename());
}

Error NotOurs(const std::string& name) {
    return Error{"--" + name, "is not a flag of this command"};
}

}  // namespace

// Each command refuses the flags that are not its own, so the CLI must know which flags the
// command line gave. It reads argv itself, as absl::ParseCommandLine will, before absl does, and
// records every name it meets. Asking absl afterwards whether a flag's CurrentValue() differs
// from its DefaultValue() would miss a flag given at its default (`lixel upload --budget=262144`
// would pass) and compares formatted strings (`--deadline=120.0` reads back as "120"); the names
// in argv are exact. That is also why the CLI refuses absl's --flagfile and --fromenv: every
// flag comes from argv. The scan refuses what absl would refuse by exiting 1 (an unknown flag, a
// value that does not parse) as an Error, which the CLI reports with exit code 2.
Result<Flags> Flags::Parse(int argc, char** argv, const char* usage_message) {
    // --help lists this file's flags, named from the source root ("client/cli/cli_options.cc").
    command_line::ListFlagsOf(__FILE__, "client/cli/cli_options.cc", usage_message);

    const command_line::ScanRules rules{
        Ours, NotOurs,
        [](const absl::CommandLineFlag& flag, const std::string&, const std::string& error) {
            return Error{"--" + std::string(flag.Name()), error + " (" + flag.Help() + ")"};
        }};
    Flags flags;
    std::vector<std::string> positional;
    for (int i = 1; i < argc; ++i) {
        std::string_view arg = argv[i];
        if (arg == "--") {  // absl: everything after is positional
            for (++i; i < argc; ++i) positional.emplace_back(argv[i]);
            break;
        }
        if (arg.size() < 2 || arg[0] != '-') {
            positional.emplace_back(arg);
            continue;
        }
        auto scanned = command_line::ScanFlag(argc, argv, i, rules);
        if (!scanned) return scanned.error();
        if (scanned->flag == nullptr) continue;  // absl's --help and friends, handled by absl
        const std::string flag_name(scanned->flag->Name());
        flags.given_.insert(flag_name);
    }
    if (positional.empty()) return Error{"lixel", "needs a command (lixel help lists them)"};
    if (positional.size() > 1) {
        return Error{positional[1],
                     "unexpected argument after the command '" + positional[0] + "' (lixel help)"};
    }
    flags.command_ = positional.front();
    absl::ParseCommandLine(argc, argv);  // --help and friends print and exit here
    return flags;
}

Result<bool> Flags::Check(const std::set<std::string>& known) const {
    for (const std::string& name : given_) {
        if (!known.contains(name) && !ConnectionFlags().contains(name)) return NotOurs(name);
    }
    return true;
}

Result<bool> Flags::CheckValues() const {
    const double deadline = absl::GetFlag(FLAGS_deadline);
    if (!(deadline > 0.0 && deadline <= kMaxDeadlineSeconds)) {
        return Error{"--deadline", "must be in (0, 86400] seconds"};
    }
    if (command_ != "solve" && absl::GetFlag(FLAGS_budget) < 1) {
        return Error{"--budget", "must be at least 1 lixel"};
    }
    const int repeats = absl::GetFlag(FLAGS_repeats);
    if (repeats < 1 || repeats > 100) return Error{"--repeats", "must be in [1, 100]"};
    if (Given("out") && absl::GetFlag(FLAGS_out).empty()) {
        return Error{"--out", "needs a folder"};
    }
    if (auto budgets = ReportBudgets(*this, {}); !budgets) return budgets.error();
    if (const int f = absl::GetFlag(FLAGS_frames); f < 1 || f > 100000) {
        return Error{"--frames", "must be in [1, 100000], got " + std::to_string(f)};
    }
    if (const int side = absl::GetFlag(FLAGS_size); side < 1 || side > kMaxImageSide) {
        return Error{"--size", "must be in [1, 16384] pixels, got " + std::to_string(side)};
    }
    if (const double w = absl::GetFlag(FLAGS_waste_bound); !(w > 0.0 && w < 1.0)) {
        return Error{"--waste_bound", "must be in (0, 1)"};
    }
    if (const int k = absl::GetFlag(FLAGS_scale_steps); k < 1 || k > 64) {
        return Error{"--scale_steps", "must be in [1, 64], got " + std::to_string(k)};
    }
    if (const double t = absl::GetFlag(FLAGS_twist_saving); !(t >= 0.0 && t < 1.0)) {
        return Error{"--twist_saving", "must be in [0, 1)"};
    }
    if (command_ == "view") {
        if (auto method = ViewMethod(); !method) return method.error();
        if (const int c = absl::GetFlag(FLAGS_cascades); c < 1 || c > 8) {
            return Error{"--cascades", "must be in [1, 8], got " + std::to_string(c)};
        }
        if (const double l = absl::GetFlag(FLAGS_split_lambda); !(l >= 0.0 && l <= 1.0)) {
            return Error{"--split_lambda", "must be in [0, 1]"};
        }
        if (auto filter = ViewFilter(); !filter) return filter.error();
        if (const double e = absl::GetFlag(FLAGS_smooth_epsilon); !(e > 0.0) || !std::isfinite(e)) {
            return Error{"--smooth_epsilon", "must be a finite length > 0"};
        }
        if (Given("normal_offset") && !(absl::GetFlag(FLAGS_normal_offset) >= 0.0)) {
            return Error{"--normal_offset", "must be a length >= 0"};
        }
    }
    return true;
}

const std::set<std::string>& ConnectionFlags() {
    static const std::set<std::string> flags = {"target",  "token",  "token_file",
                                                "tls_ca",  "tls_cert", "tls_key",
                                                "tls_server_name", "deadline"};
    return flags;
}

std::string ReadFileOrExit(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        std::fprintf(stderr, "lixel: cannot read %s\n", path.c_str());
        std::exit(2);
    }
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

// A file flag given with an empty path is read, and refused as unreadable, rather than taken
// for "none": an unset variable in a script must not quietly drop a token or TLS.
client::ClientOptions ClientOptionsFrom(const Flags& flags) {
    client::ClientOptions options;
    options.target = absl::GetFlag(FLAGS_target);
    options.bearer_token = absl::GetFlag(FLAGS_token);
    if (flags.Given("token_file")) {
        options.bearer_token = ReadFileOrExit(absl::GetFlag(FLAGS_token_file));
        while (!options.bearer_token.empty() && std::isspace(static_cast<unsigned char>(
                                                    options.bearer_token.back()))) {
            options.bearer_token.pop_back();
        }
    }
    if (flags.Given("tls_ca")) {
        options.tls_root_certificate = ReadFileOrExit(absl::GetFlag(FLAGS_tls_ca));
    }
    if (flags.Given("tls_cert")) {
        options.tls_client_certificate = ReadFileOrExit(absl::GetFlag(FLAGS_tls_cert));
    }
    if (flags.Given("tls_key")) {
        options.tls_client_key = ReadFileOrExit(absl::GetFlag(FLAGS_tls_key));
    }
    options.tls_server_name = absl::GetFlag(FLAGS_tls_server_name);
    options.deadline_seconds = absl::GetFlag(FLAGS_deadline);
    return options;
}

Result<SceneSource> LoadNamedScene(const std::string& name, bool is_file) {
    SceneSource source;
    auto scene = is_file ? scene::LoadSceneFile(name) : scene::BuiltinScene(name);
    if (!scene) return scene.error();
    source.scene = std::move(scene).value();
    service::EncodeScene(service::MakeSceneRecord(source.scene), &source.message);
    return source;
}

Result<SceneSource> LoadScene(const Flags& flags) {
    if (flags.Given("scene_file")) return LoadNamedScene(absl::GetFlag(FLAGS_scene_file), true);
    return LoadNamedScene(absl::GetFlag(FLAGS_scene), false);
}

v1::PlanRequest PlanRequestFrom(const std::string& scene_id) {
    v1::PlanRequest request;
    request.set_scene_id(scene_id);
    request.set_lixel_budget(absl::GetFlag(FLAGS_budget));
    request.set_fallback_floor(absl::GetFlag(FLAGS_fallback_floor));
    request.mutable_passes()->set_second_depth(absl::GetFlag(FLAGS_second_depth));
    request.mutable_passes()->set_silhouette_map(absl::GetFlag(FLAGS_silhouette_map));
    request.mutable_passes()->set_volumes(absl::GetFlag(FLAGS_volumes));
    return request;
}

namespace {

std::string Upper(const std::string& prefix, const std::string& name) {
    std::string out = prefix;
    for (char c : name) out += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    return out;
}

}  // namespace

Result<v1::Method> ViewMethod() {
    v1::Method method;
    if (!v1::Method_Parse(Upper("METHOD_", absl::GetFlag(FLAGS_method)), &method)) {
        return Error{"--method", "must be plane_optimal, uniform, psm, lispsm or csm"};
    }
    return method;
}

Result<v1::Filter> ViewFilter() {
    v1::Filter filter;
    if (!v1::Filter_Parse(Upper("FILTER_", absl::GetFlag(FLAGS_filter)), &filter)) {
        return Error{"--filter", "must be depth, pcf, second_depth, silhouette_map, volumes or "
                                 "smooth_volumes"};
    }
    return filter;
}

Result<v1::MapEncoding> EncodingFromFlags() {
    v1::MapEncoding encoding;
    const std::string name = absl::GetFlag(FLAGS_encoding);
    if (name == "quantised") {
        encoding.set_codec(v1::MAP_CODEC_QUANTISED);
    } else if (name == "exact") {
        encoding.set_codec(v1::MAP_CODEC_EXACT);
    } else if (name != "raw") {
        return Error{"--encoding", "must be raw, quantised or exact, not '" + name + "'"};
    }
    const std::uint32_t bits = absl::GetFlag(FLAGS_bits);
    if (bits != 0 && (name != "quantised" || bits < 16 || bits > 24)) {
        return Error{"--bits", "is N in [16, 24] with --encoding=quantised (0: chosen per map)"};
    }
    encoding.set_bits(bits);
    return encoding;
}

std::string OutFolder(const Flags& flags, const std::string& fallback) {
    return flags.Given("out") ? absl::GetFlag(FLAGS_out) : fallback;
}

Result<std::vector<std::int64_t>> ReportBudgets(const Flags& flags,
                                                std::vector<std::int64_t> fallback) {
    if (!flags.Given("budgets")) return fallback;
    const std::vector<std::string> items = absl::GetFlag(FLAGS_budgets);
    if (items.empty()) return Error{"--budgets", "needs a comma-separated list"};
    std::vector<std::int64_t> budgets;
    for (const std::string& item : items) {
        std::int64_t b = 0;
        const auto [end, ec] = std::from_chars(item.data(), item.data() + item.size(), b);
        if (ec != std::errc() || end != item.data() + item.size() || b < 1) {
            return Error{"--budgets",
                         "each budget is a positive integer of lixels, got '" + item + "'"};
        }
        budgets.push_back(b);
    }
    return budgets;
}

}  // namespace lixel::cli
