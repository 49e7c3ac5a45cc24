// Decoding a Render's coded images against the frames the client holds.
#include <lixel/client/coded_frames.h>

#include <map>

namespace lixel::client {

void CodedFrames::NameIn(v1::MapEncoding* encoding) const {
    if (encoding->reference_frames_size() != 0) return;
    // The server takes at most kMaxReferenceFrames: a frame of more images names its first ones
    // (the rest are keyframes), rather than have every later frame refused.
    for (const codec::IntegerImage& image : held_) {
        if (encoding->reference_frames_size() == codec::kMaxReferenceFrames) break;
        encoding->add_reference_frames(image.frame_id);
    }
}

Result<codec::DecodedMap> CodedFrames::Decode(const v1::RenderHeader& header, int index,
                                              std::string_view coded) {
    const std::string field = "images[" + std::to_string(index) + "]";
    const v1::MapImage& image = header.images(index);
    std::map<std::uint64_t, const codec::IntegerImage*> references;
    for (const codec::IntegerImage& held : held_) references[held.frame_id] = &held;
    // The header announced the image's size and kind: a coded image of another shape is refused
    // before its payload is read, whatever its own header claims.
    auto stated = codec::ReadHeader(coded);
    if (!stated) return Error{field + "." + stated.error().field, stated.error().reason};
    const codec::Content content =
        image.pass() == v1::PASS_SILHOUETTE_MAP ? codec::Content::kPoints : codec::Content::kDepth;
    if (stated->width != image.width() || stated->height != image.height() ||
        stated->content != content) {
        const auto name = [](codec::Content c) {
            return c == codec::Content::kPoints ? std::string(" points") : std::string(" depth");
        };
        return Error{field, "coded as " + std::to_string(stated->width) + " x " +
                                std::to_string(stated->height) + name(stated->content) +
                                ", announced " + std::to_string(image.width()) + " x " +
                                std::to_string(image.height()) + name(content)};
    }
    auto decoded = decoder_.Decode(coded, references);
    if (!decoded) return Error{field + "." + decoded.error().field, decoded.error().reason};
    return decoded;
}

void CodedFrames::Hold(std::vector<codec::IntegerImage> frame) { held_ = std::move(frame); }

}  // namespace lixel::client
