// A Render's or a session frame's maps as they arrive (client.h's checks of a broken or hostile
// server): the header checked before anything is allocated, raw chunks copied in place, coded
// chunks gathered in order within their bound, and the coded images decoded at the end.
#pragma once

#include <lixel/client/client.h>
#include <lixel/client/coded_frames.h>

#include <cstdint>
#include <string>
#include <vector>

namespace lixel::client {

class MapStream {
  public:
    // `coding`: the request asked for coded maps; `limit`: ClientOptions::max_receive_bytes.
    MapStream(bool coding, std::uint64_t limit) : coding_(coding), limit_(limit) {}

    // Each returns "" or what makes the stream malformed (the caller ends the call with it).
    std::string Header(const v1::RenderHeader& header);
    std::string Chunk(const v1::MapChunk& chunk);

    // "" once the header came and every raw image's bytes arrived, else what is missing.
    std::string Incomplete() const;

    std::uint64_t received() const noexcept { return maps_.streamed_bytes; }
    std::uint64_t total() const noexcept { return total_; }

    // The maps, coded images decoded by `decoder` and held there for the next frame's
    // references (errors name images[i] and the coded-map field).
    Result<RenderedMaps> Finish(CodedFrames& decoder);

  private:
    const bool coding_;
    const std::uint64_t limit_;
    RenderedMaps maps_;
    std::vector<std::string> coded_;
    std::vector<std::uint64_t> raw_bytes_;  // bytes received per raw image
    std::uint64_t total_ = 0;
    bool has_header_ = false;
};

}  // namespace lixel::client
