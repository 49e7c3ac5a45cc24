// lixel frames: an engine's own frames from what a Session streams (lixel::engine), one shaded PNG
// per frame and a contact sheet; with --check, each frame's mask against View's.
#include <absl/flags/flag.h>
#include <lixel/engine/frame_loop.h>

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "commands.h"

namespace lixel::cli {

namespace {

Result<engine::EngineFilter> FramesFilter() {
    const std::string name = absl::GetFlag(FLAGS_filter);
    if (name == "depth") return engine::EngineFilter::kDepth;
    if (name == "pcf") return engine::EngineFilter::kPcf;
    if (name == "second_depth") return engine::EngineFilter::kSecondDepth;
    if (name == "silhouette_map") return engine::EngineFilter::kSilhouette;
    return Error{"--filter",
                 "frames draws depth, pcf, second_depth or silhouette_map, not '" + name + "'"};
}

}  // namespace

int FramesCommand(client::Client& client, const Flags& flags) {
    auto filter = FramesFilter();
    if (!filter) return UsageError(filter.error());
    const std::int64_t max_differing = absl::GetFlag(FLAGS_max_differing);
    if (max_differing < 0) return UsageError(Error{"--max_differing", "must be >= 0"});
    engine::FramesOptions options;
    options.scene = absl::GetFlag(FLAGS_scene);
    options.frames = absl::GetFlag(FLAGS_frames);
    options.size = absl::GetFlag(FLAGS_size);
    options.budget = absl::GetFlag(FLAGS_budget);
    options.filter = *filter;
    options.check = absl::GetFlag(FLAGS_check);
    options.coherent = absl::GetFlag(FLAGS_coherent);
    auto encoding = EncodingFromFlags();
    if (!encoding) return UsageError(encoding.error());
    options.encoding = *encoding;
    auto loop = engine::FrameLoop::Create(client, options);
    if (!loop) return Fail(loop.error());
    const std::string out = OutFolder(flags, "out/frames");
    std::filesystem::create_directories(out);
    std::printf("engine: %s; %s, %d frames at %d x %d, %s, %llu lixels%s\n",
                (*loop)->renderer().c_str(), options.scene.c_str(), options.frames, options.size,
                options.size, engine::EngineFilterName(options.filter),
                static_cast<unsigned long long>(options.budget),
                options.coherent ? ", frame-coherent plans" : "");
    engine::ContactSheet sheet;
    std::vector<engine::EngineFrame> frames;
    int over = 0;
    for (int i = 0; i < options.frames; ++i) {
        auto frame = (*loop)->Run(i);
        if (!frame) return Fail(frame.error());
        char name[32];
        std::snprintf(name, sizeof(name), "/frame_%04d.png", i);
        if (auto ok = engine::WriteShadedPng(out + name, frame->images); !ok) {
            return Fail(ok.error());
        }
        sheet.Add(frame->images);
        std::printf("%s\n", engine::FrameLine(*frame).c_str());
        if (frame->check && frame->check->masks.differing + frame->check->masks.surface_mismatch >
                                max_differing) {
            ++over;
        }
        frame->images = {};  // the PNG and the sheet have it
        frames.push_back(std::move(frame).value());
    }
    if (auto ok = sheet.Write(out + "/contact_sheet.png"); !ok) return Fail(ok.error());
    std::printf("%s\n%s/frame_*.png, %s/contact_sheet.png\n",
                engine::SummaryText(engine::Summarise(frames)).c_str(), out.c_str(), out.c_str());
    if (over > 0) {
        std::fprintf(stderr,
                     "lixel: %d of %d frames have more than %lld pixels whose lit answer differs "
                     "from View's mask or where only one of them shows a surface\n",
                     over, options.frames, static_cast<long long>(max_differing));
        return 1;
    }
    return 0;
}

}  // namespace lixel::cli
