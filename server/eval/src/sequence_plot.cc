// sequence.png through gnuplot (sequence.h): per frame, each method's flicker, error and lixels.
#include <lixel/eval/sequence.h>

#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

#include "gnuplot.h"
#include "text_format.h"

namespace lixel::eval {

Result<bool> PlotSequence(const std::string& folder, const std::vector<SequenceFrameRow>& rows) {
    if (rows.empty()) return Error{"rows", "nothing to plot"};
    // One series per (method, coherent), in first-seen order, frames in order within each.
    std::vector<std::pair<std::string, bool>> series;
    for (const SequenceFrameRow& r : rows) {
        const std::pair<std::string, bool> key{r.method, r.coherent};
        if (std::find(series.begin(), series.end(), key) == series.end()) series.push_back(key);
    }
    const std::string data_path = folder + "/sequence.dat";
    const std::string script_path = folder + "/sequence.gp";
    std::ostringstream data;
    for (const auto& [method, coherent] : series) {
        std::vector<const SequenceFrameRow*> frames;
        for (const SequenceFrameRow& r : rows) {
            if (r.method == method && r.coherent == coherent) frames.push_back(&r);
        }
        std::sort(frames.begin(), frames.end(),
                  [](const auto* a, const auto* b) { return a->frame < b->frame; });
        data << "# " << method << (coherent ? " (coherent)" : "") << "\n";
        for (const SequenceFrameRow* f : frames) {
            // The first frame, and one after a skipped frame, have no flicker to report (no
            // steady pixels): a gap in the line, not a 0.
            data << f->frame << " "
                 << (f->flicker.steady == 0 ? std::string("NaN")
                                            : text::Number(f->flicker.Percent(), 6))
                 << " " << text::Number(f->error.Percent(), 6) << " " << f->total_lixels << " "
                 << f->reallocations << "\n";
        }
        data << "\n\n";
    }
    if (auto w = text::WriteText(data_path, data.str()); !w) return w.error();

    std::ostringstream gp;
    gp << "set terminal pngcairo size 960,1080 font \"sans,10\"\n"
       << "set output " << detail::GnuplotQuoted(folder + "/sequence.png") << "\n"
       << "set termoption noenhanced\n"
       << "set datafile missing \"NaN\"\n"
       << "set key outside right top\n"
       << "set lmargin at screen 0.09\n"
       << "set rmargin at screen 0.66\n"
       << "set grid\n"
       << "set multiplot layout 3,1 title " << detail::GnuplotQuoted(rows.front().scene + ", " +
                                                                    std::to_string(rows.front().budget) +
                                                                    " lixels")
       << "\n";
    const auto panel = [&](const char* title, const char* ylabel, int column) {
        gp << "set title " << detail::GnuplotQuoted(title) << "\n"
           << "set ylabel " << detail::GnuplotQuoted(ylabel) << "\n"
           << "set xlabel \"frame\"\n"
           << "plot ";
        for (std::size_t i = 0; i < series.size(); ++i) {
            const std::string label = series[i].first + (series[i].second ? " (coherent)" : "");
            gp << (i ? ", " : "") << detail::GnuplotQuoted(data_path) << " index " << i
               << " using 1:" << column << " with linespoints pt 7 ps 0.4 title "
               << detail::GnuplotQuoted(label);
        }
        // One key, beside the first panel, serves all three.
        gp << "\nunset key\n";
    };
    panel("flicker: steady pixels whose answer changed since the frame before", "flicker %", 2);
    panel("misclassified against exact visibility", "misclassified %", 3);
    panel("lixels allocated (a step: maps reallocated)", "lixels", 4);
    gp << "unset multiplot\n";
    if (auto w = text::WriteText(script_path, gp.str()); !w) return w.error();
    return detail::RunGnuplot(script_path);
}

}  // namespace lixel::eval
