// Flag parsing and scene loading for the lixel CLI.
#include "cli_options.h"

#include <lixel/scene/builtin_scenes.h>
#include <lixel/scene/scene_io.h>
#include <lixel/service/proto_convert.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace lixel::cli {

Flags::Flags(int argc, char** argv, int first) {
    for (int i = first; i < argc; ++i) {
        std::string arg = argv[i];
        if (arg.rfind("--", 0) == 0) arg = arg.substr(2);
        const auto eq = arg.find('=');
        if (eq == std::string::npos) {
            values_[arg] = "true";
        } else {
            values_[arg.substr(0, eq)] = arg.substr(eq + 1);
        }
    }
}

std::string Flags::Get(const std::string& key, const std::string& fallback) const {
    const auto it = values_.find(key);
    return it == values_.end() ? fallback : it->second;
}

Result<double> Flags::Number(const std::string& key, double fallback) const {
    const auto it = values_.find(key);
    if (it == values_.end()) return fallback;
    char* end = nullptr;
    const double value = std::strtod(it->second.c_str(), &end);
    if (it->second.empty() || *end != '\0') {
        return Error{"--" + key, "needs a number, got '" + it->second + "'"};
    }
    return value;
}

bool Flags::Bool(const std::string& key) const {
    const std::string v = Get(key, "false");
    return v == "true" || v == "1" || v == "yes";
}

Result<bool> Flags::Check(const std::set<std::string>& known) const {
    for (const auto& [key, value] : values_) {
        if (!known.contains(key) && !ConnectionFlags().contains(key)) {
            return Error{"--" + key, "is not a flag of this command"};
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

Result<client::ClientOptions> ClientOptionsFrom(const Flags& flags) {
    client::ClientOptions options;
    options.target = flags.Get("target", options.target);
    options.bearer_token = flags.Get("token");
    if (flags.Has("token_file")) {
        options.bearer_token = ReadFileOrExit(flags.Get("token_file"));
        while (!options.bearer_token.empty() && std::isspace(static_cast<unsigned char>(
                                                    options.bearer_token.back()))) {
            options.bearer_token.pop_back();
        }
    }
    if (flags.Has("tls_ca")) options.tls_root_certificate = ReadFileOrExit(flags.Get("tls_ca"));
    if (flags.Has("tls_cert")) {
        options.tls_client_certificate = ReadFileOrExit(flags.Get("tls_cert"));
    }
    if (flags.Has("tls_key")) options.tls_client_key = ReadFileOrExit(flags.Get("tls_key"));
    options.tls_server_name = flags.Get("tls_server_name");
    auto deadline = flags.Number("deadline", options.deadline_seconds);
    if (!deadline) return deadline.error();
    if (!(*deadline > 0.0)) return Error{"--deadline", "must be positive (seconds)"};
    options.deadline_seconds = *deadline;
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
    if (flags.Has("scene_file")) return LoadNamedScene(flags.Get("scene_file"), true);
    return LoadNamedScene(flags.Get("scene", "floor_wall"), false);
}

Result<v1::PlanRequest> PlanRequestFrom(const Flags& flags, const std::string& scene_id) {
    v1::PlanRequest request;
    request.set_scene_id(scene_id);
    auto budget = flags.Number("budget", 512.0 * 512.0);
    if (!budget) return budget.error();
    if (!(*budget >= 1.0)) return Error{"--budget", "must be at least 1 lixel"};
    request.set_lixel_budget(static_cast<std::uint64_t>(*budget));
    auto floor = flags.Number("fallback_floor", 0.0);
    if (!floor) return floor.error();
    request.set_fallback_floor(static_cast<std::uint64_t>(*floor));
    request.mutable_passes()->set_second_depth(flags.Bool("second_depth"));
    request.mutable_passes()->set_silhouette_map(flags.Bool("silhouette_map"));
    request.mutable_passes()->set_volumes(flags.Bool("volumes"));
    return request;
}

}  // namespace lixel::cli
