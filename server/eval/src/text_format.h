// Numbers, CSV fields and text files as lixel's report writers put them (report.cc,
// sequence.cc): one spelling of nan and inf, RFC 4180 quoting, errors that name the path.
#pragma once

#include <lixel/solver/result.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

namespace lixel::eval::text {

inline std::string Number(double value, int digits = 4) {
    if (std::isnan(value)) return "nan";
    if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
    char out[64];
    std::snprintf(out, sizeof(out), "%.*g", digits, value);
    return out;
}

inline std::string Fixed(double value, int decimals) {
    if (!std::isfinite(value)) return Number(value);
    char out[64];
    std::snprintf(out, sizeof(out), "%.*f", decimals, value);
    return out;
}

// RFC 4180: quote fields holding a comma, quote or line break; double the quotes.
inline std::string CsvField(const std::string& s) {
    if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
    std::string out = "\"";
    for (const char c : s) {
        if (c == '"') out += '"';
        out += c;
    }
    return out + "\"";
}

inline Result<bool> WriteText(const std::string& path, const std::string& content) {
    std::ofstream file(path, std::ios::binary);
    if (!file) return Error{path, "cannot open for writing"};
    file << content;
    file.close();
    if (!file) return Error{path, "write failed"};
    return true;
}

}  // namespace lixel::eval::text
