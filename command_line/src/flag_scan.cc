#include <lixel/command_line/flag_scan.h>

#include <absl/flags/reflection.h>
#include <absl/flags/usage.h>
#include <absl/flags/usage_config.h>

namespace lixel::command_line {

void ListFlagsOf(std::string_view self, std::string_view source_path, const char* usage_message) {
    absl::SetProgramUsageMessage(usage_message);
    absl::FlagsUsageConfig usage;
    const std::string self_path(self);
    const std::string source(source_path);
    usage.contains_helpshort_flags = [self_path](absl::string_view file) {
        return std::string_view(self_path).ends_with(std::string_view(file.data(), file.size()));
    };
    usage.contains_help_flags = usage.contains_helpshort_flags;
    usage.normalize_filename = [self_path, source](absl::string_view file) {
        const std::string_view s = self_path;
        std::string_view name(file.data(), file.size());
        if (s.ends_with(source) && name.starts_with(s.substr(0, s.size() - source.size()))) {
            name.remove_prefix(s.size() - source.size());
        }
        while (name.starts_with('/')) name.remove_prefix(1);
        return std::string(name);
    };
    absl::SetFlagsUsageConfig(usage);
}

bool IsUsageFlag(std::string_view name) {
    return name == "help" || name == "helpfull" || name == "helpshort" ||
           name == "helppackage" || name == "helpon" || name == "helpmatch" || name == "version" ||
           name == "only_check_args";
}

Result<ScannedFlag> ScanFlag(int argc, char** argv, int& i, const ScanRules& rules) {
    std::string_view arg = argv[i];
    arg.remove_prefix(arg.starts_with("--") ? 2 : 1);
    const auto eq = arg.find('=');
    const std::string name(arg.substr(0, eq));
    if (IsUsageFlag(name)) return ScannedFlag{};
    absl::CommandLineFlag* flag = absl::FindCommandLineFlag(name);
    bool negated = false;
    if (flag == nullptr && name.starts_with("no")) {
        flag = absl::FindCommandLineFlag(name.substr(2));
        negated = flag != nullptr && flag->IsOfType<bool>();
        if (!negated) flag = nullptr;
    }
    if (flag == nullptr || !rules.ours(*flag)) return rules.not_ours(name);
    std::string value;
    if (eq != std::string_view::npos) {
        if (negated) return Error{"--" + name, "takes no value"};
        value = arg.substr(eq + 1);
    } else if (flag->IsOfType<bool>()) {
        value = negated ? "false" : "true";
    } else if (i + 1 < argc) {
        value = argv[++i];  // "--flag value"
    } else {
        return Error{"--" + name, "needs a value (" + flag->Help() + ")"};
    }
    // A trial parse: the value ParseCommandLine then sets is the same.
    std::string error;
    if (!flag->ParseFrom(value, &error)) return rules.bad_value(*flag, value, error);
    return ScannedFlag{flag, value};
}

}  // namespace lixel::command_line
