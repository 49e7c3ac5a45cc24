// Writers (and readers, for round trips and the client) of maps and previews: PFM and OpenEXR
// for float maps, PNG for previews (DESIGN §7-8).
#pragma once

#include <lixel/render/image.h>
#include <lixel/solver/result.h>

#include <string>

namespace lixel::render {

// Portable float map: "Pf" (1 channel) or "PF" (3; a 2-channel image is written with a zero
// third channel), little-endian (scale -1), rows bottom to top as the format defines.
Result<bool> WritePfm(const std::string& path, const FloatImage& image);
Result<FloatImage> ReadPfm(const std::string& path);

// OpenEXR, 32-bit float channels "Y" (1), "R","G" (2), "R","G","B" (3), "R","G","B","A" (4),
// zip-compressed, rows top to bottom as the format defines (flipped on write and read).
Result<bool> WriteExr(const std::string& path, const FloatImage& image);
Result<FloatImage> ReadExr(const std::string& path);

// 8-bit RGB PNG, rows top to bottom (flipped on write and read).
Result<bool> WritePng(const std::string& path, const Rgb8Image& image);
Result<Rgb8Image> ReadPng(const std::string& path);

// A mask as an 8-bit grey preview: lit fraction 0..1 -> 0..255, kNoSurface -> blue.
Rgb8Image MaskPreview(const FloatImage& mask);

}  // namespace lixel::render
