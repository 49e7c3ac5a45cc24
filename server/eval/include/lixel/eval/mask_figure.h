// The report's labelled mask grid (DESIGN §7, issue 12): per scene one row per method (fitting +
// shadow test), one column per budget, each cell the method's mask as its difference from the
// truth (png_image.h's palette: light and dark grey where it agrees, red false lit, blue false
// shadow, yellow undecided, dark blue-grey no surface), with the shaded preview and the truth
// above the grid and a legend for the colours. Drawn by gnuplot from tile PNGs.
#pragma once

#include <lixel/eval/image.h>
#include <lixel/solver/result.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace lixel::eval {

// Tiles are box-filtered (Shrink) until no side exceeds this many pixels.
inline constexpr int kMaskTileSide = 224;

class MaskFigure {
  public:
    struct Row {
        std::string method;
        std::vector<std::optional<RgbImage>> cells;  // per budget; empty: the run was skipped
    };

    // `truth` is TruthImage of the scene's ground truth; `budgets` are the columns, in order.
    MaskFigure(std::string scene, const RgbImage& truth, std::vector<std::int64_t> budgets);

    // The cell of `method` (a row, created in first-seen order) at `budget` (one of the
    // columns; others are ignored), shrunk to a tile. `difference` is DifferenceImage.
    void Add(const std::string& method, std::int64_t budget, const RgbImage& difference);
    // Names the row of a run that was skipped (its cell stays empty and says so).
    void Skip(const std::string& method);
    // The same image in every column: a method that uses no lixels (silhouette volumes).
    void AddToEveryBudget(const std::string& method, const RgbImage& difference);
    // The view pass's shaded preview and what it shows ("plane-optimal + depth, 512²").
    void SetPreview(const RgbImage& preview, std::string label);

    const std::string& scene() const noexcept { return scene_; }
    const std::vector<std::int64_t>& budgets() const noexcept { return budgets_; }
    const std::vector<Row>& rows() const noexcept { return rows_; }
    const RgbImage& truth() const noexcept { return truth_; }
    const std::optional<RgbImage>& preview() const noexcept { return preview_; }
    const std::string& preview_label() const noexcept { return preview_label_; }

  private:
    Row& RowOf(const std::string& method);

    std::string scene_;
    RgbImage truth_;
    std::vector<std::int64_t> budgets_;
    std::vector<Row> rows_;
    std::optional<RgbImage> preview_;
    std::string preview_label_;
};

// <folder>/<scene>_masks.png through gnuplot: the tiles are written under <folder>/<scene>_masks/
// and the script beside the image (<scene>_masks.gp). Errors name the file or carry gnuplot's.
Result<bool> PlotMaskFigure(const std::string& folder, const MaskFigure& figure);

// The same tiles without labels (preview and truth first, then a row per method), for when
// gnuplot is not available.
RgbImage UnlabelledMaskFigure(const MaskFigure& figure);

}  // namespace lixel::eval
