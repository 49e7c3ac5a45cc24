// A terminal progress bar with the time remaining, for long sweeps (DESIGN §7). On a terminal it
// redraws one line; into a file or pipe it prints a line every 10% so logs stay readable.
#pragma once

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>

namespace lixel::eval {

class ProgressBar {
  public:
    // `total` >= 1 steps; `out` defaults to stderr.
    ProgressBar(std::int64_t total, std::string label, std::FILE* out = stderr);
    ~ProgressBar();

    // Marks `steps` more as done; `item` names what finished last (shown on the line).
    void Advance(std::int64_t steps = 1, std::string_view item = {});
    // Prints the final line (idempotent; the destructor calls it).
    void Finish();

    std::int64_t done() const { return done_; }

    // The line for `done` of `total` after `elapsed_s` seconds: a bar `width` characters wide,
    // the count, the elapsed time and the remaining time extrapolated linearly.
    static std::string Format(std::string_view label, std::int64_t done, std::int64_t total,
                              double elapsed_s, int width, std::string_view item);
    // "42s", "3m07s", "1h02m".
    static std::string FormatDuration(double seconds);

  private:
    void Draw(bool final_line);

    std::int64_t total_;
    std::int64_t done_ = 0;
    std::string label_;
    std::string item_;
    std::FILE* out_;
    bool terminal_;
    bool finished_ = false;
    int last_decile_ = -1;
    std::chrono::steady_clock::time_point start_;
};

}  // namespace lixel::eval
