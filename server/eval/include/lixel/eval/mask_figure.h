// The report's labelled mask grids (DESIGN §7, issues 12 and 25): per scene one grid per shadow
// test (depth, PCF, second depth, silhouette map, shadow volumes), a row per fitting and a column
// per budget, each cell the method's mask as its difference from the truth (png_image.h's
// palette: light and dark grey where it agrees, red false lit, blue false shadow, yellow
// undecided, dark blue-grey no surface), with the shaded preview, the truth and a legend above
// each grid. A grid holds the five to seven fittings a reader compares, each a tile's height from
// the truth, where one grid of every method was 66 rows (4 926 px on long_floor). Drawn by gnuplot
// from tile PNGs.
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

// The grid a method's name belongs to: "plane-optimal (uniform scale) + PCF" is the row
// "plane-optimal (uniform scale)" of the grid "PCF"; a name without a shadow test (the silhouette
// volumes, which use no lixels) is a row of its own in the grid kVolumesGrid.
inline constexpr const char* kVolumesGrid = "shadow volumes";
struct MaskGridPlace {
    std::string grid;
    std::string row;
};
MaskGridPlace MaskGridPlaceOf(const std::string& method);

// "<scene>_masks_<grid>.png", the grid's name in lower case with '_' for anything but letters
// and digits: floor_wall_masks_depth.png, floor_wall_masks_second_depth.png.
std::string MaskGridFile(const std::string& scene, const std::string& grid);

struct MaskGrid {
    struct Row {
        std::string label;                           // the fitting
        std::vector<std::optional<RgbImage>> cells;  // per budget; empty: the run was skipped
    };
    std::string name;  // the shadow test
    std::vector<Row> rows;
};

class MaskFigure {
  public:
    // `truth` is TruthImage of the scene's ground truth; `budgets` are the columns, in order.
    MaskFigure(std::string scene, const RgbImage& truth, std::vector<std::int64_t> budgets);

    // The cell of `method` (its grid and row created in first-seen order) at `budget` (one of
    // the columns; others are ignored), shrunk to a tile. `difference` is DifferenceImage.
    void Add(const std::string& method, std::int64_t budget, const RgbImage& difference);
    // Names the row of a run that was skipped (its cell stays empty and says so).
    void Skip(const std::string& method);
    // The same image in every column: a method that uses no lixels (silhouette volumes).
    void AddToEveryBudget(const std::string& method, const RgbImage& difference);
    // The view pass's shaded preview and what it shows ("plane-optimal + depth, 512²").
    void SetPreview(const RgbImage& preview, std::string label);

    const std::string& scene() const noexcept { return scene_; }
    const std::vector<std::int64_t>& budgets() const noexcept { return budgets_; }
    const std::vector<MaskGrid>& grids() const noexcept { return grids_; }
    const RgbImage& truth() const noexcept { return truth_; }
    const std::optional<RgbImage>& preview() const noexcept { return preview_; }
    const std::string& preview_label() const noexcept { return preview_label_; }

  private:
    MaskGrid::Row& RowOf(const std::string& method);

    std::string scene_;
    RgbImage truth_;
    std::vector<std::int64_t> budgets_;
    std::vector<MaskGrid> grids_;
    std::optional<RgbImage> preview_;
    std::string preview_label_;
};

// Each grid as <folder>/MaskGridFile(scene, grid) through gnuplot: its tiles under
// <folder>/<scene>_masks_<grid>/ and its script beside the image (.gp). Returns the PNGs' names
// in the grids' order. Errors name the file or carry gnuplot's.
Result<std::vector<std::string>> PlotMaskFigure(const std::string& folder,
                                                const MaskFigure& figure);

// One grid's tiles without labels (preview and truth first, then a row per fitting), for when
// gnuplot is not available.
RgbImage UnlabelledMaskGrid(const MaskFigure& figure, const MaskGrid& grid);

// The figure's grids as PNGs: labelled when `labelled` and gnuplot is available
// (PlotMaskFigure), else UnlabelledMaskGrid. The names written, and whether they are labelled.
struct WrittenMaskGrids {
    std::vector<std::string> files;
    bool labelled = false;
};
Result<WrittenMaskGrids> WriteMaskFigure(const std::string& folder, const MaskFigure& figure,
                                         bool labelled);

// The note a report gives for WriteMaskFigure's grids: their names and how to read them.
std::string MaskFigureNote(const WrittenMaskGrids& written, bool volumes_repeat);

}  // namespace lixel::eval
