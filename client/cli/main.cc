// lixel: the command-line thin client. `lixel <command> [--flags]`; `lixel help` lists them.
#include <cstdio>
#include <set>
#include <string>

#include "commands.h"

namespace {

constexpr const char* kUsage =
    "usage: lixel <command> [--target=HOST:PORT[,...]] [--token=T] [--tls_ca=PEM]\n"
    "             [--tls_cert=PEM --tls_key=PEM] [--deadline=SECONDS] [flags]\n"
    "commands:\n"
    "  upload  --scene=NAME | --scene_file=PATH     upload, print the scene id\n"
    "  solve   --scene=... [--budget=N] [--twist]   plane-optimal matrices only\n"
    "  plan    --scene=... [--budget=N] [--second_depth] [--silhouette_map]\n"
    "          [--volumes]                          what would be rendered, why\n"
    "  render  --scene=... [--budget=N] [--out=DIR] [--pfm]\n"
    "                                               maps as OpenEXR (or PFM) + PNG\n"
    "  view    --scene=... [--method=plane_optimal|uniform|psm|lispsm|csm]\n"
    "          [--filter=depth|pcf|second_depth|silhouette_map|volumes|smooth_volumes]\n"
    "          [--cascades=4] [--split_lambda=0.5] [--stable_cascades]  (csm)\n"
    "          [--smooth_epsilon=0.001] [--normal_offset=D]  (smooth_volumes)\n"
    "          [--evaluate] [--timings] [--out=DIR]  the per-pixel mask\n"
    "  report  --scene=... | --all [--full] [--repeats=N] [--budgets=N,N,...] [--out=DIR]\n"
    "                                               error against run time\n"
    "  sequence --scene=... [--frames=60] [--size=512] [--budget=N] [--fallback_floor=N]\n"
    "          [--out=DIR] [--waste_bound=0.25] [--scale_steps=4] [--twist_saving=0.1]\n"
    "                                               flicker and reallocations per method\n"
    "  frames  --scene=... [--frames=60] [--size=512] [--budget=N]\n"
    "          [--filter=depth|pcf|second_depth] [--out=DIR] [--check] [--max_differing=8]\n"
    "          [--coherent]\n"
    "                                               an engine's own frames from Render\n"
    "scenes: floor_wall (default), table_floor, sphere_grid, thin_plates,\n"
    "        sphere_torus, pins; or a scene file (docs/scenes.md)\n"
    "lixel <command> --help lists every flag with its default.\n";

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2 || std::string(argv[1]) == "help" || std::string(argv[1]) == "--help") {
        std::fputs(kUsage, stderr);
        return argc < 2 ? 2 : 0;
    }
    auto flags = lixel::cli::Flags::Parse(argc, argv, kUsage);
    if (!flags) return lixel::cli::UsageError(flags.error());
    const std::string& command = flags->command();
    const std::set<std::string>* known = lixel::cli::CommandFlags(command);
    if (known == nullptr) {
        std::fprintf(stderr, "lixel: unknown command '%s'\n", command.c_str());
        std::fputs(kUsage, stderr);
        return 2;
    }
    if (auto ok = flags->Check(*known); !ok) return lixel::cli::UsageError(ok.error());
    if (auto ok = flags->CheckValues(); !ok) return lixel::cli::UsageError(ok.error());
    auto client = lixel::client::Client::Connect(lixel::cli::ClientOptionsFrom(*flags));
    if (!client) return lixel::cli::Fail(client.error());
    lixel::client::Client& c = **client;
    if (command == "upload") return lixel::cli::UploadCommand(c, *flags);
    if (command == "solve") return lixel::cli::SolveCommand(c, *flags);
    if (command == "plan") return lixel::cli::PlanCommand(c, *flags);
    if (command == "render") return lixel::cli::RenderCommand(c, *flags);
    if (command == "view") return lixel::cli::ViewCommand(c, *flags);
    if (command == "report") return lixel::cli::ReportCommand(c, *flags);
    if (command == "sequence") return lixel::cli::SequenceCommand(c, *flags);
    if (command == "frames") return lixel::cli::FramesCommand(c, *flags);
    return lixel::cli::UsageError({command, "has flags but no handler"});  // a table out of step
}
