// Command-line parsing shared by the lixel CLI's commands: --key=value flags after a command.
#pragma once

#include <lixel/client/client.h>
#include <lixel/scene/scene.h>
#include <lixel/solver/result.h>
#include <lixel/v1/lixel.pb.h>

#include <map>
#include <set>
#include <string>
#include <vector>

namespace lixel::cli {

class Flags {
public:
    // Parses argv[first..]; a flag without '=' is "true". Unknown flags are reported by Check.
    Flags(int argc, char** argv, int first);

    std::string Get(const std::string& key, const std::string& fallback = "") const;
    bool Has(const std::string& key) const { return values_.contains(key); }
    Result<double> Number(const std::string& key, double fallback) const;
    bool Bool(const std::string& key) const;
    // Refuses flags not in `known`, naming the first.
    Result<bool> Check(const std::set<std::string>& known) const;

private:
    std::map<std::string, std::string> values_;
};

// Client options from --target, --token, --token_file, --tls_ca, --tls_cert, --tls_key,
// --tls_server_name, --deadline.
Result<client::ClientOptions> ClientOptionsFrom(const Flags& flags);
const std::set<std::string>& ConnectionFlags();

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
Result<v1::PlanRequest> PlanRequestFrom(const Flags& flags, const std::string& scene_id);

std::string ReadFileOrExit(const std::string& path);

}  // namespace lixel::cli
