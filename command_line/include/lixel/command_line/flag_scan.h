// The command line as absl::ParseCommandLine will read it, read first by the program itself, so
// that it knows exactly which flags were given (a flag given at its default included) and
// refuses, with its own message, a flag that is not its own. `lixel` and `lixel_server` share it.
#pragma once

#include <absl/flags/commandlineflag.h>
#include <lixel/solver/result.h>

#include <functional>
#include <string>
#include <string_view>

namespace lixel::command_line {

// absl's --help and --helpfull list only the flags defined in `self` (the caller's __FILE__),
// named from the source root as `source_path` ("server/main.cc") wherever the tree was built.
void ListFlagsOf(std::string_view self, std::string_view source_path, const char* usage_message);

// absl's usage flags (--help and friends), which absl handles itself.
bool IsUsageFlag(std::string_view name);

struct ScannedFlag {
    const absl::CommandLineFlag* flag = nullptr;  // null: a usage flag, left to absl
    std::string value;                            // as absl will set it
};

struct ScanRules {
    std::function<bool(const absl::CommandLineFlag&)> ours;  // the program's own flags
    std::function<Error(const std::string& name)> not_ours;  // the refusal of any other
    // The refusal of a value the flag does not parse (absl's `error`).
    std::function<Error(const absl::CommandLineFlag& flag, const std::string& value,
                        const std::string& error)>
        bad_value;
};

// The flag argv[i] names ("--name=value", "--name value", "--name" or "--noname" for a bool;
// argv[i] starts with '-' and is not "--"), its value trial-parsed as absl will parse it; `i`
// moves past a separate value. Errors name "--name": one `rules.ours` refuses, a value given to
// "--noname", a missing value, or one that does not parse.
Result<ScannedFlag> ScanFlag(int argc, char** argv, int& i, const ScanRules& rules);

}  // namespace lixel::command_line
