// gnuplot as a child process (gnuplot.h, GnuplotAvailable in report.h).
#include "gnuplot.h"

#include <fcntl.h>
#include <lixel/eval/report.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <iterator>
#include <vector>

#ifndef LIXEL_GNUPLOT_PATH
#define LIXEL_GNUPLOT_PATH "gnuplot"
#endif

extern char** environ;

namespace lixel::eval {
namespace {

// Runs `program args...` with stdout and stderr into `log`; returns the exit status or -1.
int Run(const std::vector<std::string>& argv, const std::string& log) {
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(),
                                     O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
    std::vector<char*> args;
    for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    pid_t pid = 0;
    const int spawned = posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (spawned != 0) return -1;
    int status = 0;
    if (waitpid(pid, &status, 0) != pid) return -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace

bool GnuplotAvailable() { return Run({LIXEL_GNUPLOT_PATH, "--version"}, "/dev/null") == 0; }

namespace detail {

std::string GnuplotQuoted(const std::string& s) {
    std::string out = "\"";
    for (const char c : s) {
        if (c == '\n') {
            out += "\\n";  // gnuplot breaks the line at \n in a double-quoted string
            continue;
        }
        if (c == '"' || c == '\\') out += '\\';
        out += c;
    }
    return out + "\"";
}

Result<bool> RunGnuplot(const std::string& script_path) {
    const std::string log = script_path + ".log";
    const int status = Run({LIXEL_GNUPLOT_PATH, script_path}, log);
    if (status != 0) {
        std::ifstream in(log);
        std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        return Error{script_path, "gnuplot exited with " + std::to_string(status) +
                                      (text.empty() ? std::string() : ": " + text)};
    }
    std::remove(log.c_str());
    return true;
}

}  // namespace detail
}  // namespace lixel::eval
