#include "pipelines/commands/targets_command.h"

#include <fmt/format.h>

#include <sstream>
#include <vector>

#include "pipelines/commands/common_flags.h"
#include "pipelines/formats/dot_colors.h"
#include "pipelines/formats/test_plan.h"
#include "pipelines/targets/printable_targets.h"
#include "util/atomic_file.h"
#include "util/input_error.h"

namespace softbench {

void AddTargetsCommand(CLI::App* c, TargetsCommandOptions* options) {
  AddOutOption(c, &options->output_dir,
               "folder for tag, checkerboard and dots .pdf and .svg "
               "(replaced whole)")
      ->required();
  CLI::Option* plan =
      c->add_option("--plan", options->plan_path,
                    "test plan: print its tag (id, size_mm) and its markers' "
                    "dots (colour, diameter, count)");
  c->add_option("--tag-id", options->tag_id, "tag36h11 id (without --plan)")
      ->capture_default_str()
      ->excludes(plan);
  c->add_option("--tag-mm", options->tag_mm,
                "tag's black border, edge to edge [mm] (without --plan)")
      ->capture_default_str()
      ->excludes(plan);
  c->add_option("--dot-colors", options->dot_colors,
                "one head per colour, comma-separated: " + DotColorNames() +
                    " (without --plan)")
      ->capture_default_str()
      ->excludes(plan);
  c->add_option("--dot-mm", options->dot_mm,
                "dot diameter [mm] (without --plan)")
      ->capture_default_str()
      ->excludes(plan);
  c->add_option("--dots-per-head", options->dots_per_head,
                "dots on each head (without --plan)")
      ->capture_default_str()
      ->excludes(plan);
  c->add_option("--board", options->board,
                "checkerboard inner corners per row x per column")
      ->capture_default_str();
  c->add_option("--square-mm", options->square_mm,
                "checkerboard square side [mm]")
      ->capture_default_str();
  c->add_option("--paper", options->paper, "a4 or letter")
      ->capture_default_str();
}

namespace {

// The dot groups the plan's markers need, one per head.
std::vector<DotGroup> DotGroupsFromPlan(const TestPlan& plan) {
  std::vector<DotGroup> groups;
  for (const MarkerSpec& marker : plan.markers) {
    const DotColor* color = FindDotColor(marker.color);
    groups.push_back(
        {fmt::format("head {} ({})", plan.mechanism.heads[marker.head].name,
                     marker.color),
         color->ink_bgr, marker.dot_diameter_mm, marker.dots});
  }
  return groups;
}

std::vector<DotGroup> DotGroupsFromFlags(const TargetsCommandOptions& o) {
  std::vector<DotGroup> groups;
  std::stringstream list(o.dot_colors);
  std::string name;
  while (std::getline(list, name, ',')) {
    const DotColor* color = FindDotColor(name);
    if (color == nullptr) {
      throw InputError("--dot-colors: '" + name + "' is not " +
                       DotColorNames());
    }
    groups.push_back({fmt::format("head {} ({})", groups.size(), name),
                      color->ink_bgr, o.dot_mm, o.dots_per_head});
  }
  return groups;
}

}  // namespace

int RunTargets(const TargetsCommandOptions& o, std::ostream& out) {
  const Paper* paper = FindPaper(o.paper);
  if (paper == nullptr) {
    throw InputError("--paper: '" + o.paper + "' is not a4 or letter");
  }
  SheetOptions sheet;
  sheet.paper = *paper;
  TagSheetOptions tag;
  tag.sheet = sheet;
  DotSheetOptions dots;
  dots.sheet = sheet;
  std::string tag_source = "--tag-mm", dot_source = "--dot-mm";
  if (!o.plan_path.empty()) {
    const TestPlan plan = LoadTestPlan(o.plan_path);
    if (!plan.calibration.tag) {
      throw InputError(o.plan_path +
                       ": calibration has no tag to print; add "
                       "calibration.tag (family, id, size_mm) or drop --plan");
    }
    tag.id = plan.calibration.tag->id;
    tag.size_mm = plan.calibration.tag->size_mm;
    dots.groups = DotGroupsFromPlan(plan);
    tag_source = o.plan_path + ": calibration.tag.size_mm";
    dot_source = o.plan_path + ": markers";
  } else {
    if (o.tag_id < 0 || o.tag_id >= kTag36h11Codes) {
      throw InputError(
          fmt::format("--tag-id: {} is not a tag36h11 id (0 to {})", o.tag_id,
                      kTag36h11Codes - 1));
    }
    tag.id = o.tag_id;
    tag.size_mm = o.tag_mm;
    dots.groups = DotGroupsFromFlags(o);
  }
  if (auto problem = tag.Problem())
    throw InputError(tag_source + ": " + *problem);
  if (auto problem = dots.Problem()) {
    throw InputError(dot_source + ": " + *problem);
  }
  CheckerboardSheetOptions board;
  board.sheet = sheet;
  board.board = ParseBoardFlag(o.board, o.square_mm);
  if (auto problem = board.Problem()) {
    throw InputError("--board: " + *problem);
  }
  CheckOutputDirectory(o.output_dir, "--out");
  CheckOutputsSpareInputs({{"--plan", o.plan_path}}, {},
                          {{"--out", o.output_dir}});
  AtomicDirectory directory(o.output_dir);
  for (const auto& [format, ext] :
       {std::pair{SheetFormat::kPdf, ".pdf"}, {SheetFormat::kSvg, ".svg"}}) {
    WriteFileAtomically(directory.File(std::string("tag") + ext),
                        DrawTagSheet(tag, format));
    WriteFileAtomically(directory.File(std::string("checkerboard") + ext),
                        DrawCheckerboardSheet(board, format));
    WriteFileAtomically(directory.File(std::string("dots") + ext),
                        DrawDotSheet(dots, format));
  }
  directory.Commit();
  out << fmt::format(
      "wrote tag (tag36h11 id {}, {:.1f} mm), checkerboard ({}x{} inner "
      "corners, {:.1f} mm squares) and dots ({} head{}), each .pdf and .svg "
      "for {}, to {}\n"
      "print at 100 % (actual size) and measure each sheet's black bar "
      "before use\n",
      tag.id, tag.size_mm, board.board.corners_x, board.board.corners_y,
      board.board.square_mm, dots.groups.size(),
      dots.groups.size() == 1 ? "" : "s", paper->name, o.output_dir);
  return 0;
}

}  // namespace softbench
