// Command-line parsing shared by the lixel CLI's commands: `lixel <command> --name=value ...`.
// Every flag of every command is an absl flag (defined in cli_options.cc, read with
// absl::GetFlag(FLAGS_name)); Flags records which of them the command line gave, so that each
// command refuses the ones that are not its own.
#pragma once

#include <absl/flags/declare.h>
#include <lixel/client/client.h>
#include <lixel/scene/scene.h>
#include <lixel/solver/result.h>
#include <lixel/v1/lixel.pb.h>

#include <cstdint>
#include <set>
#include <string>
#include <string_view>
#include <vector>

// Connection, every command: --target, --token, --token_file, --tls_ca, --tls_cert, --tls_key,
// --tls_server_name, --deadline (seconds per call, (0, 86400]).
ABSL_DECLARE_FLAG(std::string, target);
ABSL_DECLARE_FLAG(std::string, encoding);
ABSL_DECLARE_FLAG(std::uint32_t, bits);
ABSL_DECLARE_FLAG(int, cascades);
ABSL_DECLARE_FLAG(double, split_lambda);
ABSL_DECLARE_FLAG(bool, stable_cascades);
ABSL_DECLARE_FLAG(double, smooth_epsilon);
ABSL_DECLARE_FLAG(double, normal_offset);
ABSL_DECLARE_FLAG(std::string, token);
ABSL_DECLARE_FLAG(std::string, token_file);
ABSL_DECLARE_FLAG(std::string, tls_ca);
ABSL_DECLARE_FLAG(std::string, tls_cert);
ABSL_DECLARE_FLAG(std::string, tls_key);
ABSL_DECLARE_FLAG(std::string, tls_server_name);
ABSL_DECLARE_FLAG(double, deadline);
// The scene: --scene (built in, default floor_wall) or --scene_file (docs/scenes.md).
ABSL_DECLARE_FLAG(std::string, scene);
ABSL_DECLARE_FLAG(std::string, scene_file);
// The plan of plan, render and view; --budget is also solve's per-map budget.
ABSL_DECLARE_FLAG(std::uint64_t, budget);
ABSL_DECLARE_FLAG(std::uint64_t, fallback_floor);
ABSL_DECLARE_FLAG(bool, second_depth);
ABSL_DECLARE_FLAG(bool, silhouette_map);
ABSL_DECLARE_FLAG(bool, volumes);
// solve, render, view, report.
ABSL_DECLARE_FLAG(bool, twist);
ABSL_DECLARE_FLAG(std::string, out);
ABSL_DECLARE_FLAG(bool, pfm);
ABSL_DECLARE_FLAG(std::string, method);
ABSL_DECLARE_FLAG(std::string, filter);
ABSL_DECLARE_FLAG(bool, evaluate);
ABSL_DECLARE_FLAG(bool, timings);
ABSL_DECLARE_FLAG(bool, all);
ABSL_DECLARE_FLAG(bool, full);
ABSL_DECLARE_FLAG(bool, depth_only);
ABSL_DECLARE_FLAG(int, repeats);
ABSL_DECLARE_FLAG(std::vector<std::string>, budgets);
// sequence and frames: the frame sequence (scene::SequenceOptions).
ABSL_DECLARE_FLAG(int, frames);
ABSL_DECLARE_FLAG(int, size);
// sequence: FrameCoherence's settings for the coherent rows.
ABSL_DECLARE_FLAG(double, waste_bound);
ABSL_DECLARE_FLAG(int, scale_steps);
ABSL_DECLARE_FLAG(double, twist_saving);
// frames: compare with View's mask, and the most differing pixels a frame may have.
ABSL_DECLARE_FLAG(bool, check);
ABSL_DECLARE_FLAG(bool, coherent);
ABSL_DECLARE_FLAG(std::int64_t, max_differing);

namespace lixel::cli {

class Flags {
public:
    // Parses argv with absl::ParseCommandLine; the command is the one positional argument.
    // An unknown flag, a value absl cannot parse, a missing or second command is an Error
    // (usage_message is what absl's --help prints first).
    static Result<Flags> Parse(int argc, char** argv, const char* usage_message);

    const std::string& command() const { return command_; }
    // Whether the command line named the flag (--name, --name=..., --noname), whatever value.
    bool Given(std::string_view name) const { return given_.contains(std::string(name)); }
    // Refuses a given flag that is neither in `known` nor a connection flag, naming the first.
    Result<bool> Check(const std::set<std::string>& known) const;
    // What absl's types do not express: the ranges of --deadline, --budget (plan, render, view),
    // --repeats and --budgets, a given --out that is empty, view's --method and --filter.
    Result<bool> CheckValues() const;

private:
    std::string command_;
    std::set<std::string> given_;
};

const std::set<std::string>& ConnectionFlags();

// Client options from the connection flags.
client::ClientOptions ClientOptionsFrom(const Flags& flags);

// The scene a command works on: --scene=NAME (built in, default floor_wall) or
// --scene_file=PATH (docs/scenes.md). Uploaded on first use.
struct SceneSource {
    scene::Scene scene;
    v1::Scene message;
};
Result<SceneSource> LoadScene(const Flags& flags);
// A built-in scene by name, or a scene file when `name` ends in a path.
Result<SceneSource> LoadNamedScene(const std::string& name, bool is_file);

// The PlanRequest for a scene id with --budget, --fallback_floor, --second_depth,
// --silhouette_map, --volumes; the scene's own camera, light and planes.
v1::PlanRequest PlanRequestFrom(const std::string& scene_id);

// view's --method and --filter.
Result<v1::Method> ViewMethod();
Result<v1::Filter> ViewFilter();

// --out when given, else the command's own folder.
// --encoding and --bits as a RenderRequest's encoding; errors name the flag.
Result<v1::MapEncoding> EncodingFromFlags();

std::string OutFolder(const Flags& flags, const std::string& fallback);

// report's --budgets (a comma-separated list of positive lixel counts), else `fallback`.
Result<std::vector<std::int64_t>> ReportBudgets(const Flags& flags,
                                                std::vector<std::int64_t> fallback);

std::string ReadFileOrExit(const std::string& path);

}  // namespace lixel::cli
