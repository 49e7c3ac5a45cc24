// A mesh file's extension, lower case ("model.GLB" -> ".glb"): what picks its decoder.
#pragma once

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <string>

namespace lixel::scene {

inline std::string LowerExtension(const std::string& path) {
    std::string s = std::filesystem::path(path).extension().string();
    std::transform(s.begin(), s.end(), s.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return s;
}

}  // namespace lixel::scene
