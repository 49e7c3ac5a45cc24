// lixel_report: the error-vs-run-time report (issue 6). Flags only; the work is RunReport.
//   lixel_report [--out DIR] [--sweep] [--scene NAME|FILE.scene]... [--methods depth|all]
//                [--budgets 65536,262144,...] [--repeats N] [--size WxH] [--gl egl|osmesa]
//                [--no-plot] [--quiet]
#include <lixel/scene/builtin_scenes.h>
#include <lixel/eval/report_runner.h>

#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>

namespace {

int Usage(const char* error) {
    if (error) std::fprintf(stderr, "lixel_report: %s\n", error);
    std::fprintf(stderr,
                 "usage: lixel_report [--out DIR] [--sweep] [--scene NAME|FILE.scene]...\n"
                 "                    [--methods depth|all] [--budgets N,N,...] [--repeats N]\n"
                 "                    [--size WxH] [--gl egl|osmesa] [--no-plot] [--quiet]\n"
                 "  default: the floor_wall scene, every method, budgets 256^2, 512^2, 1024^2\n"
                 "  --sweep: every built-in scene\n"
                 "  --repeats: timed repeats per run after one untimed warm-up (default 5)\n");
    return error ? 2 : 0;
}

}  // namespace

int main(int argc, char** argv) {
    lixel::eval::ReportOptions options;
    bool scenes_given = false;
    for (int i = 1; i < argc; ++i) {
        const std::string flag = argv[i];
        auto value = [&]() -> const char* { return i + 1 < argc ? argv[++i] : nullptr; };
        if (flag == "--help" || flag == "-h") return Usage(nullptr);
        if (flag == "--sweep") {
            options.scenes = lixel::scene::BuiltinSceneNames();
            scenes_given = true;
        } else if (flag == "--scene") {
            const char* v = value();
            if (!v) return Usage("--scene needs a name or a .scene file");
            if (!scenes_given) options.scenes.clear();
            scenes_given = true;
            options.scenes.push_back(v);
        } else if (flag == "--out") {
            const char* v = value();
            if (!v) return Usage("--out needs a folder");
            options.output = v;
        } else if (flag == "--methods") {
            const char* v = value();
            if (!v) return Usage("--methods needs depth or all");
            const std::string m = v;
            if (m == "depth") {
                options.methods = lixel::eval::DepthMethods();
            } else if (m == "all") {
                options.methods = lixel::eval::AllMethods();
            } else {
                return Usage("--methods: expected depth or all");
            }
        } else if (flag == "--budgets") {
            const char* v = value();
            if (!v) return Usage("--budgets needs a comma-separated list");
            options.budgets.clear();
            std::stringstream list(v);
            for (std::string item; std::getline(list, item, ',');) {
                char* end = nullptr;
                const long long b = std::strtoll(item.c_str(), &end, 10);
                if (end == item.c_str() || *end != '\0' || b < 1) {
                    return Usage("--budgets: each budget is a positive integer of lixels");
                }
                options.budgets.push_back(b);
            }
        } else if (flag == "--repeats") {
            const char* v = value();
            if (!v || std::atoi(v) < 1) return Usage("--repeats needs a positive integer");
            options.repeats = std::atoi(v);
        } else if (flag == "--size") {
            const char* v = value();
            int w = 0, h = 0;
            if (!v || std::sscanf(v, "%dx%d", &w, &h) != 2 || w < 1 || h < 1 ||
                w > lixel::kMaxImageSide || h > lixel::kMaxImageSide) {
                return Usage("--size: expected WxH, each in [1, 16384]");
            }
            options.viewport = lixel::Viewport{w, h};
        } else if (flag == "--gl") {
            const char* v = value();
            auto backend = lixel::render::ParseBackend(v ? v : "", "--gl");
            if (!backend) return Usage(backend.error().Message().c_str());
            options.gl.backend = *backend;
        } else if (flag == "--no-plot") {
            options.plot = false;
        } else if (flag == "--quiet") {
            options.progress = false;
        } else {
            return Usage(("unknown flag " + flag).c_str());
        }
    }
    auto summary = lixel::eval::RunReport(options);
    if (!summary) {
        std::fprintf(stderr, "lixel_report: %s\n", summary.error().Message().c_str());
        return 1;
    }
    for (const std::string& note : summary->notes) std::printf("%s\n", note.c_str());
    std::printf("wrote");
    for (const std::string& f : summary->files)
        std::printf(" %s/%s", options.output.c_str(), f.c_str());
    std::printf("\n");
    return 0;
}
