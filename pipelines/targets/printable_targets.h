#ifndef SOFTBENCH_PIPELINES_TARGETS_PRINTABLE_TARGETS_H_
#define SOFTBENCH_PIPELINES_TARGETS_PRINTABLE_TARGETS_H_

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "calibration/camera_calibration.h"

namespace softbench {

// A sheet of paper, portrait [mm].
struct Paper {
  std::string_view name;
  double width_mm = 0.0;
  double height_mm = 0.0;
};

// A4 or US letter by name ("a4", "letter"), or null.
const Paper* FindPaper(std::string_view name);

enum class SheetFormat { kPdf, kSvg };

// What every sheet shares: the paper and the margin a printer cannot reach.
struct SheetOptions {
  Paper paper = *FindPaper("a4");
  // Kept blank on every side; most printers cannot print the outer 5 mm.
  double margin_mm = 12.0;

  std::optional<std::string> Problem() const;
};

// The AprilTag that gives a validation its scale and axes (the plan's
// calibration.tag), with a ruler and bars to check the print's scale.
struct TagSheetOptions {
  SheetOptions sheet;
  int id = 0;             // tag36h11 id
  double size_mm = 50.0;  // black border, outer edge to outer edge
  // Length of the horizontal and vertical check bars [mm] (printers can
  // scale the two axes differently); 0: the tag's size.
  double check_bar_mm = 0.0;

  // The first bad field and what it must be (including "does not fit").
  std::optional<std::string> Problem() const;
};

// The checkerboard `calibrate-camera` looks for.
struct CheckerboardSheetOptions {
  SheetOptions sheet;
  BoardOptions board;  // inner corners and square side

  std::optional<std::string> Problem() const;
};

// One head's dot stickers (a plan marker).
struct DotGroup {
  std::string label;             // e.g. "head 0 (red)"
  std::array<int, 3> ink_bgr{};  // the plan colour's ink
  double diameter_mm = 4.0;
  int dots_per_head = 3;
};

struct DotSheetOptions {
  SheetOptions sheet;
  std::vector<DotGroup> groups;
  // Stickers printed per needed dot: spares for the ones that tear.
  int sets = 4;

  std::optional<std::string> Problem() const;
};

// Each sheet's file contents (PDF or SVG, drawn with cairo at exact size);
// the options must pass Problem().
std::string DrawTagSheet(const TagSheetOptions& options, SheetFormat format);
std::string DrawCheckerboardSheet(const CheckerboardSheetOptions& options,
                                  SheetFormat format);
std::string DrawDotSheet(const DotSheetOptions& options, SheetFormat format);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_TARGETS_PRINTABLE_TARGETS_H_
