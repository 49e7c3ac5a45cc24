// Running gnuplot as a child process, for the report's figures (plot.cc, mask_figure.cc).
// Internal to lixel::eval.
#pragma once

#include <lixel/solver/result.h>

#include <string>

namespace lixel::eval::detail {

// A gnuplot string literal: double-quoted, with quotes and backslashes escaped and line breaks
// as \n (which gnuplot breaks the line at).
std::string GnuplotQuoted(const std::string& s);

// Runs gnuplot on `script_path` with its output into `script_path` + ".log", removed on success.
// Errors name the script and carry gnuplot's exit status and messages.
Result<bool> RunGnuplot(const std::string& script_path);

}  // namespace lixel::eval::detail
