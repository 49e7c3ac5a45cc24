// The labelled mask grids (mask_figure.h): per grid its tiles as PNGs, a gnuplot multiplot that
// places each one at its pixel rectangle, then one last empty plot that carries every label and
// the legend (labels set before the image plots would be drawn again with each of them).
#include <lixel/eval/mask_figure.h>
#include <lixel/eval/png_image.h>
#include <lixel/eval/report.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <sstream>
#include <string_view>

#include "gnuplot.h"
#include "text_format.h"

namespace lixel::eval {
namespace {

namespace fs = std::filesystem;
using detail::GnuplotQuoted;

// Canvas layout, pixels.
constexpr int kGap = 6;
constexpr int kLabelColumn = 230;  // row labels; the top row's legend
constexpr int kTitle = 34;
constexpr int kCaption = 22;     // above the budget columns
constexpr int kTopCaption = 34;  // two lines above the preview and the truth

std::string Hex(const std::uint8_t (&c)[3]) {
    char text[8];
    std::snprintf(text, sizeof(text), "#%02x%02x%02x", c[0], c[1], c[2]);
    return text;
}

// Where a tile goes, in pixels from the canvas' bottom left.
struct Box {
    int x = 0, y = 0, w = 0, h = 0;
};

struct Layout {
    int tile_w = 0, tile_h = 0, columns = 0, width = 0, height = 0;

    // Slot (column, row): row 0 is the preview/truth row, rows 1.. the fittings.
    Box Slot(int column, int row) const {
        const int top = height - kTitle - kTopCaption;  // top edge of row 0's tiles
        const int y0 = row == 0 ? top - tile_h
                                : top - tile_h - kGap - kCaption - row * (tile_h + kGap) + kGap;
        return {kLabelColumn + kGap + column * (tile_w + kGap), y0, tile_w, tile_h};
    }
};

Layout LayoutOf(const MaskFigure& figure, const MaskGrid& grid) {
    Layout l;
    l.tile_w = std::max(1, figure.truth().width);
    l.tile_h = std::max(1, figure.truth().height);
    // The top row holds the preview and the truth: at least two slots wide.
    l.columns = std::max<int>(2, static_cast<int>(figure.budgets().size()));
    l.width = kLabelColumn + kGap + l.columns * (l.tile_w + kGap);
    const int rows = static_cast<int>(grid.rows.size());
    l.height = kTitle + kTopCaption + l.tile_h + kGap + kCaption + rows * (l.tile_h + kGap) + kGap;
    return l;
}

std::string Screen(double pixels, int extent) {
    std::ostringstream s;
    s << pixels / extent;
    return s.str();
}

// A script's lines that draw the grid's tiles, each at its box; the tile PNGs go under `dir`.
class TileScript {
  public:
    TileScript(std::ostringstream& gp, const Layout& l) : gp_(gp), l_(l) {}

    // Each tile fills its box exactly: the plot area pinned in screen coordinates, one pixel of
    // the tile per unit.
    Result<bool> Place(const RgbImage& tile, const fs::path& file, const Box& b) {
        if (auto ok = WritePng(file.string(), tile); !ok) return ok;
        gp_ << "set lmargin at screen " << Screen(b.x, l_.width) << "\nset rmargin at screen "
            << Screen(b.x + b.w, l_.width) << "\nset bmargin at screen " << Screen(b.y, l_.height)
            << "\nset tmargin at screen " << Screen(b.y + b.h, l_.height) << "\nset xrange [-0.5:"
            << tile.width - 0.5 << "]\nset yrange [-0.5:" << tile.height - 0.5 << "]\n"
            << "plot " << GnuplotQuoted(file.string())
            << " binary filetype=png with rgbimage notitle\n";
        return true;
    }

    void Text(const std::string& s, double x, double y, const char* align,
              const char* font = "") {
        gp_ << "set label " << ++label_ << " " << GnuplotQuoted(s) << " at screen "
            << Screen(x, l_.width) << "," << Screen(y, l_.height) << " " << align;
        if (*font) gp_ << " font " << GnuplotQuoted(font);
        gp_ << " front\n";
    }

    void Swatch(const std::uint8_t (&colour)[3], double y, double half_height) {
        gp_ << "set object " << ++object_ << " rectangle from screen " << Screen(8, l_.width)
            << "," << Screen(y - half_height, l_.height) << " to screen " << Screen(22, l_.width)
            << "," << Screen(y + half_height, l_.height) << " fillcolor rgb \"" << Hex(colour)
            << "\" fillstyle solid 1.0 border lc rgb \"black\" front\n";
    }

  private:
    std::ostringstream& gp_;
    const Layout& l_;
    int label_ = 0;
    int object_ = 0;
};

Result<bool> PlaceTiles(TileScript& script, const Layout& l, const MaskFigure& figure,
                        const MaskGrid& grid, const fs::path& dir) {
    if (figure.preview()) {
        if (auto ok = script.Place(*figure.preview(), dir / "preview.png", l.Slot(0, 0)); !ok) {
            return ok;
        }
    }
    if (auto ok = script.Place(figure.truth(), dir / "truth.png", l.Slot(1, 0)); !ok) return ok;
    for (std::size_t r = 0; r < grid.rows.size(); ++r) {
        for (std::size_t c = 0; c < grid.rows[r].cells.size(); ++c) {
            if (!grid.rows[r].cells[c]) continue;
            // Appended, not "r" + std::to_string(r): GCC 12 warns falsely (-Wrestrict) there.
            const fs::path file = dir / std::string("r").append(std::to_string(r))
                                            .append("_c")
                                            .append(std::to_string(c))
                                            .append(".png");
            const Box b = l.Slot(static_cast<int>(c), static_cast<int>(r) + 1);
            if (auto ok = script.Place(*grid.rows[r].cells[c], file, b); !ok) return ok;
        }
    }
    return true;
}

void WriteLabels(TileScript& script, const Layout& l, const MaskFigure& figure,
                 const MaskGrid& grid) {
    script.Text(figure.scene() + ", " + grid.name + ": masks against the truth", l.width / 2.0,
                l.height - kTitle / 2.0, "center", "sans,12");
    const Box preview = l.Slot(0, 0), truth = l.Slot(1, 0);
    script.Text(figure.preview() ? "shaded preview\n" + figure.preview_label() : "no preview",
                preview.x + preview.w / 2.0, preview.y + preview.h + kTopCaption / 2.0,
                "center");
    script.Text("truth\n(ray cast)", truth.x + truth.w / 2.0,
                truth.y + truth.h + kTopCaption / 2.0, "center");
    for (std::size_t c = 0; c < figure.budgets().size(); ++c) {
        const Box b = l.Slot(static_cast<int>(c), 1);
        script.Text(BudgetLabel(figure.budgets()[c]) + " lixels", b.x + b.w / 2.0,
                    b.y + b.h + kCaption / 2.0, "center", "sans,10");
    }
    for (std::size_t r = 0; r < grid.rows.size(); ++r) {
        const Box b = l.Slot(0, static_cast<int>(r) + 1);
        script.Text(grid.rows[r].label, kLabelColumn, b.y + b.h / 2.0, "right", "sans,10");
        for (std::size_t c = 0; c < grid.rows[r].cells.size(); ++c) {
            if (grid.rows[r].cells[c]) continue;
            const Box e = l.Slot(static_cast<int>(c), static_cast<int>(r) + 1);
            script.Text("skipped (see notes)", e.x + e.w / 2.0, e.y + e.h / 2.0, "center");
        }
    }
}

// The difference colours, in the label column beside the preview.
void WriteLegend(TileScript& script, const Layout& l) {
    const struct {
        const std::uint8_t (&colour)[3];
        const char* meaning;
    } legend[] = {{Palette::kLit, "lit, agrees with the truth"},
                  {Palette::kShadow, "shadow, agrees"},
                  {Palette::kFalseLit, "false lit (truth: shadow)"},
                  {Palette::kFalseShadow, "false shadow (truth: lit)"},
                  {Palette::kUndecided, "undecided (not counted)"},
                  {Palette::kEmpty, "no surface"}};
    const Box preview = l.Slot(0, 0);
    const int entries = static_cast<int>(std::size(legend));
    const double step = std::min(18.0, double(preview.h + kTopCaption) / entries);
    for (int i = 0; i < entries; ++i) {
        const double y = preview.y + preview.h + kTopCaption - (i + 0.5) * step;
        script.Swatch(legend[i].colour, y, step * 0.35);
        script.Text(legend[i].meaning, 28, y, "left");
    }
}

Result<std::string> PlotMaskGrid(const std::string& folder, const MaskFigure& figure,
                                 const MaskGrid& grid) {
    const std::string png = MaskGridFile(figure.scene(), grid.name);
    const std::string stem = png.substr(0, png.size() - 4);
    const fs::path dir = fs::path(folder) / stem;
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) return Error{dir.string(), "cannot create: " + ec.message()};
    const Layout l = LayoutOf(figure, grid);
    std::ostringstream gp;
    gp << "# Generated by lixel::eval::PlotMaskFigure.\n"
       << "set terminal pngcairo size " << l.width << "," << l.height << " font \"sans,9\"\n"
       << "set encoding utf8\n"
       << "set output " << GnuplotQuoted((fs::path(folder) / png).string())
       << "\nset termoption noenhanced\n"
       << "set multiplot\n"
       << "unset key\nunset border\nunset tics\n";
    TileScript script(gp, l);
    if (auto ok = PlaceTiles(script, l, figure, grid, dir); !ok) return ok.error();
    WriteLabels(script, l, figure, grid);
    WriteLegend(script, l);
    gp << "set lmargin at screen 0\nset rmargin at screen 1\nset bmargin at screen 0\n"
       << "set tmargin at screen 1\nset xrange [0:1]\nset yrange [0:1]\n"
       << "plot NaN notitle\nunset multiplot\n";

    const std::string path = (fs::path(folder) / (stem + ".gp")).string();
    if (auto ok = text::WriteText(path, gp.str()); !ok) return ok.error();
    if (auto ok = detail::RunGnuplot(path); !ok) return ok.error();
    return png;
}

}  // namespace

MaskGridPlace MaskGridPlaceOf(const std::string& method) {
    constexpr std::string_view kJoin = " + ";  // Method::Name(): "<fitting> + <test>"
    const std::size_t at = method.rfind(kJoin);
    if (at == std::string::npos) return {kVolumesGrid, method};
    return {method.substr(at + kJoin.size()), method.substr(0, at)};
}

std::string MaskGridFile(const std::string& scene, const std::string& grid) {
    std::string slug;
    for (const char c : grid) {
        const bool keep = std::isalnum(static_cast<unsigned char>(c)) != 0;
        slug += keep ? static_cast<char>(std::tolower(static_cast<unsigned char>(c))) : '_';
    }
    return scene + "_masks_" + slug + ".png";
}

MaskFigure::MaskFigure(std::string scene, const RgbImage& truth, std::vector<std::int64_t> budgets)
    : scene_(std::move(scene)),
      truth_(Shrink(truth, kMaskTileSide)),
      budgets_(std::move(budgets)) {}

MaskGrid::Row& MaskFigure::RowOf(const std::string& method) {
    MaskGridPlace place = MaskGridPlaceOf(method);
    auto grid = std::find_if(grids_.begin(), grids_.end(),
                             [&](const MaskGrid& g) { return g.name == place.grid; });
    if (grid == grids_.end()) {
        grids_.push_back({std::move(place.grid), {}});
        grid = grids_.end() - 1;
    }
    for (MaskGrid::Row& r : grid->rows) {
        if (r.label == place.row) return r;
    }
    grid->rows.push_back(
        {std::move(place.row), std::vector<std::optional<RgbImage>>(budgets_.size())});
    return grid->rows.back();
}

void MaskFigure::Add(const std::string& method, std::int64_t budget, const RgbImage& difference) {
    const auto it = std::find(budgets_.begin(), budgets_.end(), budget);
    MaskGrid::Row& row = RowOf(method);
    if (it != budgets_.end()) row.cells[it - budgets_.begin()] = Shrink(difference, kMaskTileSide);
}

void MaskFigure::Skip(const std::string& method) { RowOf(method); }

void MaskFigure::AddToEveryBudget(const std::string& method, const RgbImage& difference) {
    const RgbImage tile = Shrink(difference, kMaskTileSide);
    for (std::optional<RgbImage>& cell : RowOf(method).cells) cell = tile;
}

void MaskFigure::SetPreview(const RgbImage& preview, std::string label) {
    preview_ = Shrink(preview, kMaskTileSide);
    preview_label_ = std::move(label);
}

Result<std::vector<std::string>> PlotMaskFigure(const std::string& folder,
                                                const MaskFigure& figure) {
    std::vector<std::string> files;
    for (const MaskGrid& grid : figure.grids()) {
        auto file = PlotMaskGrid(folder, figure, grid);
        if (!file) return file.error();
        files.push_back(std::move(file).value());
    }
    return files;
}

RgbImage UnlabelledMaskGrid(const MaskFigure& figure, const MaskGrid& grid) {
    const RgbImage& truth = figure.truth();
    const RgbImage blank(truth.width, truth.height, 255);
    const std::size_t columns = std::max<std::size_t>(2, figure.budgets().size());
    std::vector<RgbImage> tiles = {figure.preview() ? *figure.preview() : blank, truth};
    tiles.resize(columns, blank);
    for (const MaskGrid::Row& row : grid.rows) {
        for (std::size_t c = 0; c < columns; ++c) {
            tiles.push_back(c < row.cells.size() && row.cells[c] ? *row.cells[c] : blank);
        }
    }
    return ImageGrid(tiles, static_cast<int>(columns));
}

Result<WrittenMaskGrids> WriteMaskFigure(const std::string& folder, const MaskFigure& figure,
                                         bool labelled) {
    WrittenMaskGrids written;
    if (labelled && GnuplotAvailable()) {
        auto files = PlotMaskFigure(folder, figure);
        if (!files) return files.error();
        written.files = std::move(files).value();
        written.labelled = true;
        return written;
    }
    for (const MaskGrid& grid : figure.grids()) {
        const std::string file = MaskGridFile(figure.scene(), grid.name);
        if (auto ok =
                WritePng((fs::path(folder) / file).string(), UnlabelledMaskGrid(figure, grid));
            !ok) {
            return ok.error();
        }
        written.files.push_back(file);
    }
    return written;
}

std::string MaskFigureNote(const WrittenMaskGrids& written, bool volumes_repeat) {
    std::string names;
    for (const std::string& f : written.files) names += (names.empty() ? "" : ", ") + f;
    if (!written.labelled) {
        return names + ": unlabelled (gnuplot not available or off): one grid per shadow test, "
                       "the preview and the truth, then a row per fitting in the tables' order "
                       "and a column per budget; grey agrees, red false lit, blue false shadow, "
                       "yellow undecided";
    }
    return names + ": one grid per shadow test, a row per fitting and a column per budget, each "
                   "cell the mask's difference from the truth (legend in the figure), the shaded "
                   "preview and the truth above" +
           std::string(volumes_repeat ? "; silhouette volumes use no lixels, so their rows "
                                        "repeat one run"
                                      : "");
}

}  // namespace lixel::eval
