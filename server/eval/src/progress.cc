// Terminal progress bar (progress.h).
#include <lixel/eval/progress.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <utility>

namespace lixel::eval {

ProgressBar::ProgressBar(std::int64_t total, std::string label, std::FILE* out)
    : total_(std::max<std::int64_t>(1, total)),
      label_(std::move(label)),
      out_(out ? out : stderr),
      terminal_(isatty(fileno(out_)) != 0),
      start_(std::chrono::steady_clock::now()) {
    Draw(false);
}

ProgressBar::~ProgressBar() { Finish(); }

void ProgressBar::Advance(std::int64_t steps, std::string_view item) {
    done_ = std::min(total_, done_ + std::max<std::int64_t>(0, steps));
    item_ = std::string(item);
    Draw(false);
}

void ProgressBar::Finish() {
    if (finished_) return;
    finished_ = true;
    Draw(true);
}

std::string ProgressBar::FormatDuration(double seconds) {
    if (!std::isfinite(seconds) || seconds < 0) return "?";
    const long s = std::lround(seconds);
    char text[32];
    if (s < 60) {
        std::snprintf(text, sizeof(text), "%lds", s);
    } else if (s < 3600) {
        std::snprintf(text, sizeof(text), "%ldm%02lds", s / 60, s % 60);
    } else {
        std::snprintf(text, sizeof(text), "%ldh%02ldm", s / 3600, (s / 60) % 60);
    }
    return text;
}

std::string ProgressBar::Format(std::string_view label, std::int64_t done, std::int64_t total,
                                double elapsed_s, int width, std::string_view item) {
    total = std::max<std::int64_t>(1, total);
    done = std::clamp<std::int64_t>(done, 0, total);
    const double fraction = double(done) / double(total);
    const int filled = static_cast<int>(std::floor(fraction * width));
    std::string bar(static_cast<std::size_t>(filled), '#');
    bar.resize(static_cast<std::size_t>(std::max(0, width)), '.');
    std::string line = std::string(label) + " [" + bar + "] " + std::to_string(done) + "/" +
                       std::to_string(total) + "  " + FormatDuration(elapsed_s) + " elapsed";
    if (done < total) {
        // Linear extrapolation; unknown until the first step is done.
        line += ", ";
        line += done > 0 ? FormatDuration(elapsed_s * double(total - done) / double(done))
                         : std::string("?");
        line += " left";
    }
    if (!item.empty()) {
        line += "  ";
        line += item;
    }
    return line;
}

void ProgressBar::Draw(bool final_line) {
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    const std::string line = Format(label_, done_, total_, elapsed, 30, item_);
    if (terminal_) {
        // \x1b[K clears what a longer previous line left behind.
        std::fprintf(out_, "\r%s\x1b[K%s", line.c_str(), final_line ? "\n" : "");
    } else {
        const int decile = static_cast<int>(10 * done_ / total_);
        if (decile == last_decile_ && !final_line) return;
        if (final_line && decile == last_decile_ && done_ == total_) return;
        last_decile_ = decile;
        std::fprintf(out_, "%s\n", line.c_str());
    }
    std::fflush(out_);
}

}  // namespace lixel::eval
