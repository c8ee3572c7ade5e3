#include "pipelines/targets/printable_targets.h"

#include <cairo-pdf.h>
#include <cairo-svg.h>
#include <cairo.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>

#include "util/check.h"
#include "util/version.h"
#include "vision/tag_bitmap.h"

namespace softbench {
namespace {

constexpr double kPointsPerMm = 72.0 / 25.4;
constexpr Paper kPapers[] = {{"a4", 210.0, 297.0}, {"letter", 215.9, 279.4}};

// Heights of the lines of text [mm] (about 14, 9 and 8 pt).
constexpr double kTitleMm = 5.0;
constexpr double kTextMm = 3.2;
constexpr double kSmallMm = 2.8;
// Room a sheet's title and instructions take at its top [mm].
constexpr double kHeaderMm = 20.0;
// Room the ruler and its labels take [mm].
constexpr double kRulerMm = 14.0;
// Thickness of a check bar [mm].
constexpr double kBarMm = 1.5;
// The dot sheet's check bar [mm]: a 2 % scale error shows as 1 mm.
constexpr double kDotCheckBarMm = 50.0;

cairo_status_t AppendBytes(void* closure, const unsigned char* data,
                           unsigned int length) {
  static_cast<std::string*>(closure)->append(
      reinterpret_cast<const char*>(data), length);
  return CAIRO_STATUS_SUCCESS;
}

// One page `width_mm` x `height_mm`, drawn by `draw` in millimetres from the
// top-left corner, as PDF or SVG.
std::string RenderSheet(double width_mm, double height_mm, SheetFormat format,
                        const std::string& title,
                        const std::function<void(cairo_t*)>& draw) {
  std::string bytes;
  cairo_surface_t* surface = nullptr;
  double units_per_mm = 1.0;
  if (format == SheetFormat::kPdf) {
    // PDF pages are measured in points.
    units_per_mm = kPointsPerMm;
    surface = cairo_pdf_surface_create_for_stream(
        AppendBytes, &bytes, width_mm * units_per_mm, height_mm * units_per_mm);
    cairo_pdf_surface_set_metadata(surface, CAIRO_PDF_METADATA_TITLE,
                                   title.c_str());
    const std::string creator =
        std::string("softbench ") + SoftbenchVersion() + " targets";
    cairo_pdf_surface_set_metadata(surface, CAIRO_PDF_METADATA_CREATOR,
                                   creator.c_str());
  } else {
    // Cairo 1.16 writes the surface's size with the document unit's name but
    // does not convert it, so the SVG is drawn in millimetres throughout:
    // width="210mm" viewBox="0 0 210 297", what a browser or Inkscape prints
    // at true size.
    surface = cairo_svg_surface_create_for_stream(AppendBytes, &bytes, width_mm,
                                                  height_mm);
    cairo_svg_surface_set_document_unit(surface, CAIRO_SVG_UNIT_MM);
  }
  cairo_t* cr = cairo_create(surface);
  cairo_scale(cr, units_per_mm, units_per_mm);
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL,
                         CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_source_rgb(cr, 0, 0, 0);
  draw(cr);
  SOFTBENCH_CHECK(cairo_status(cr) == CAIRO_STATUS_SUCCESS)
      << cairo_status_to_string(cairo_status(cr));
  cairo_destroy(cr);
  cairo_surface_finish(surface);
  SOFTBENCH_CHECK(cairo_surface_status(surface) == CAIRO_STATUS_SUCCESS)
      << cairo_status_to_string(cairo_surface_status(surface));
  cairo_surface_destroy(surface);
  return bytes;
}

enum class Align { kLeft, kCentre };

// A line of text whose baseline starts (or is centred) at (x, y) [mm].
void Text(cairo_t* cr, double x, double y, double height_mm,
          const std::string& text, Align align = Align::kLeft) {
  cairo_set_font_size(cr, height_mm);
  cairo_text_extents_t extents;
  cairo_text_extents(cr, text.c_str(), &extents);
  const double left = align == Align::kCentre ? x - extents.x_advance / 2.0 : x;
  cairo_move_to(cr, left, y);
  cairo_show_text(cr, text.c_str());
}

// The title and the instruction every sheet carries.
void Header(cairo_t* cr, const SheetOptions& sheet, const std::string& title,
            const std::string& subtitle) {
  const double x = sheet.margin_mm;
  Text(cr, x, sheet.margin_mm + kTitleMm, kTitleMm, title);
  Text(cr, x, sheet.margin_mm + kTitleMm + 5.5, kTextMm, subtitle);
  Text(cr, x, sheet.margin_mm + kTitleMm + 10.0, kTextMm,
       "Print at 100 % (\"actual size\", never \"fit to page\"), then "
       "measure the bar with a ruler before use.");
}

// A millimetre ruler `length_mm` long whose zero is at (x, y); ticks hang
// below the line, every centimetre labelled.
void Ruler(cairo_t* cr, double x, double y, int length_mm) {
  cairo_set_line_width(cr, 0.15);
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_BUTT);
  cairo_move_to(cr, x, y);
  cairo_line_to(cr, x + length_mm, y);
  for (int mm = 0; mm <= length_mm; ++mm) {
    const double tick = mm % 10 == 0 ? 4.0 : mm % 5 == 0 ? 2.8 : 1.8;
    cairo_move_to(cr, x + mm, y);
    cairo_line_to(cr, x + mm, y + tick);
  }
  cairo_stroke(cr);
  for (int mm = 0; mm <= length_mm; mm += 10) {
    Text(cr, x + mm, y + 4.0 + kSmallMm + 0.5, kSmallMm,
         mm == length_mm ? fmt::format("{} mm", mm) : fmt::format("{}", mm),
         Align::kCentre);
  }
}

// A solid bar exactly `length_mm` long from (x, y), along x or down y, with
// "measure this" beside it.
void CheckBar(cairo_t* cr, double x, double y, double length_mm,
              bool vertical) {
  const std::string label = fmt::format("measure this: {:.1f} mm", length_mm);
  if (vertical) {
    cairo_rectangle(cr, x, y, kBarMm, length_mm);
    cairo_fill(cr);
    cairo_save(cr);
    cairo_translate(cr, x - 1.0, y + length_mm / 2.0);
    cairo_rotate(cr, -std::numbers::pi / 2.0);
    Text(cr, 0.0, 0.0, kSmallMm, label, Align::kCentre);
    cairo_restore(cr);
  } else {
    Text(cr, x, y - 1.2, kSmallMm, label);
    cairo_rectangle(cr, x, y, length_mm, kBarMm);
    cairo_fill(cr);
  }
}

// The tag sheet's layout on the paper [mm].
struct TagLayout {
  double quiet_mm = 0.0;  // the tag with its white quiet zone
  double left_mm = 0.0, top_mm = 0.0;
  double bar_mm = 0.0;
  double bar_y_mm = 0.0;
  double ruler_y_mm = 0.0;
  // Room for the tag's white square and for the bars.
  double max_quiet_mm = 0.0;
  double max_bar_mm = 0.0;
};

TagLayout LayOutTag(const TagSheetOptions& o, const TagBitmap& bitmap) {
  const SheetOptions& s = o.sheet;
  TagLayout l;
  l.quiet_mm = o.size_mm * bitmap.total_width / bitmap.width_at_border;
  const double inner_w = s.paper.width_mm - 2.0 * s.margin_mm;
  const double inner_h = s.paper.height_mm - 2.0 * s.margin_mm;
  // The vertical bar and its label take 8 mm at the right; below the tag, a
  // caption, the horizontal bar and the ruler.
  const double below_mm = 8.0 + 10.0 + kRulerMm;
  l.max_quiet_mm = std::min(inner_w - 16.0, inner_h - kHeaderMm - below_mm);
  l.left_mm = s.margin_mm + (inner_w - 8.0 - l.quiet_mm) / 2.0;
  l.top_mm = s.margin_mm + kHeaderMm;
  l.bar_y_mm = l.top_mm + l.quiet_mm + 14.0;
  l.ruler_y_mm = s.paper.height_mm - s.margin_mm - kRulerMm + 2.0;
  l.max_bar_mm = std::min(inner_w - 8.0, inner_h - kHeaderMm - kRulerMm);
  l.bar_mm = o.check_bar_mm > 0.0
                 ? o.check_bar_mm
                 : std::min(o.size_mm, std::floor(l.max_bar_mm / 10.0) * 10.0);
  return l;
}

// The checkerboard's orientation and place on the paper [mm].
struct BoardLayout {
  double page_w_mm = 0.0, page_h_mm = 0.0;
  double left_mm = 0.0, top_mm = 0.0;
  double width_mm = 0.0, height_mm = 0.0;
  bool fits = false;
  double largest_square_mm = 0.0;  // that fits, for messages
};

BoardLayout LayOutBoard(const CheckerboardSheetOptions& o) {
  const SheetOptions& s = o.sheet;
  const int nx = o.board.corners_x + 1, ny = o.board.corners_y + 1;
  BoardLayout best;
  // Portrait, then landscape; the one with room for the larger square wins.
  for (const bool landscape : {false, true}) {
    BoardLayout l;
    l.page_w_mm = landscape ? s.paper.height_mm : s.paper.width_mm;
    l.page_h_mm = landscape ? s.paper.width_mm : s.paper.height_mm;
    const double room_w = l.page_w_mm - 2.0 * s.margin_mm;
    // Below the board its check bar; the ruler only where there is room.
    const double room_h = l.page_h_mm - 2.0 * s.margin_mm - kHeaderMm - 8.0;
    l.largest_square_mm = std::min(room_w / nx, room_h / ny);
    l.width_mm = nx * o.board.square_mm;
    l.height_mm = ny * o.board.square_mm;
    l.fits = l.width_mm <= room_w && l.height_mm <= room_h;
    l.left_mm = (l.page_w_mm - l.width_mm) / 2.0;
    l.top_mm = s.margin_mm + kHeaderMm;
    if (l.largest_square_mm > best.largest_square_mm) best = l;
  }
  return best;
}

// Where dot stickers go: centre-to-centre pitch and rows per group [mm].
double DotPitchMm(const DotGroup& g) {
  return g.diameter_mm + std::max(3.0, 0.6 * g.diameter_mm);
}

int DotsPerRow(const SheetOptions& s, const DotGroup& g) {
  const double room = s.paper.width_mm - 2.0 * s.margin_mm;
  return std::max(1, static_cast<int>((room + DotPitchMm(g) - g.diameter_mm) /
                                      DotPitchMm(g)));
}

// The height one group takes: its label and its rows of dots.
double DotGroupHeightMm(const SheetOptions& s, const DotGroup& g, int sets) {
  const int dots = g.dots_per_head * sets;
  const int rows = (dots + DotsPerRow(s, g) - 1) / DotsPerRow(s, g);
  return 7.0 + rows * DotPitchMm(g);
}

}  // namespace

const Paper* FindPaper(std::string_view name) {
  for (const Paper& paper : kPapers) {
    if (paper.name == name) return &paper;
  }
  return nullptr;
}

std::optional<std::string> SheetOptions::Problem() const {
  if (!(paper.width_mm > 0.0 && paper.height_mm > 0.0)) {
    return "the paper's size must be > 0";
  }
  if (!(margin_mm >= 0.0) ||
      2.0 * margin_mm >= std::min(paper.width_mm, paper.height_mm)) {
    return "the margin must be >= 0 and leave room on the paper";
  }
  return std::nullopt;
}

std::optional<std::string> TagSheetOptions::Problem() const {
  if (auto problem = sheet.Problem()) return problem;
  if (id < 0) return "the tag id must be >= 0";
  if (!(size_mm >= 10.0)) {
    return fmt::format(
        "a {} mm tag is too small to print sharply; use 10 mm "
        "or more",
        size_mm);
  }
  if (!(check_bar_mm >= 0.0)) return "the check bar's length must be >= 0";
  const TagBitmap bitmap = Tag36h11Bitmap(0);
  const TagLayout l = LayOutTag(*this, bitmap);
  if (l.quiet_mm > l.max_quiet_mm) {
    return fmt::format(
        "a {} mm tag ({:.1f} mm with its white border) does not fit on {} "
        "with {} mm margins; tags up to {:.1f} mm fit",
        size_mm, l.quiet_mm, sheet.paper.name, sheet.margin_mm,
        l.max_quiet_mm * bitmap.width_at_border / bitmap.total_width);
  }
  if (l.bar_mm > l.max_bar_mm) {
    return fmt::format("a {} mm check bar does not fit; up to {:.0f} mm does",
                       l.bar_mm, l.max_bar_mm);
  }
  return std::nullopt;
}

std::optional<std::string> CheckerboardSheetOptions::Problem() const {
  if (auto problem = sheet.Problem()) return problem;
  if (auto problem = board.Problem()) return problem;
  const BoardLayout l = LayOutBoard(*this);
  if (!l.fits) {
    return fmt::format(
        "a {} x {} board of {} mm squares ({:.0f} x {:.0f} mm) does not fit "
        "on {} with {} mm margins; squares up to {:.1f} mm fit",
        board.corners_x, board.corners_y, board.square_mm, l.width_mm,
        l.height_mm, sheet.paper.name, sheet.margin_mm,
        std::floor(l.largest_square_mm * 10.0) / 10.0);
  }
  return std::nullopt;
}

std::optional<std::string> DotSheetOptions::Problem() const {
  if (auto problem = sheet.Problem()) return problem;
  if (groups.empty()) return "no dots to print";
  if (sets < 1) return "sets must be >= 1";
  double height = kHeaderMm + 8.0;  // and the check bar
  for (const DotGroup& g : groups) {
    if (!(g.diameter_mm >= 1.0) ||
        g.diameter_mm > sheet.paper.width_mm - 2.0 * sheet.margin_mm) {
      return fmt::format("{}: a {} mm dot cannot be printed on {}", g.label,
                         g.diameter_mm, sheet.paper.name);
    }
    if (g.dots_per_head < 1) return g.label + ": needs at least one dot";
    height += DotGroupHeightMm(sheet, g, sets);
  }
  if (height > sheet.paper.height_mm - 2.0 * sheet.margin_mm) {
    return fmt::format(
        "the dots take {:.0f} mm, more than one {} page; print fewer sets",
        height, sheet.paper.name);
  }
  return std::nullopt;
}

std::string DrawTagSheet(const TagSheetOptions& o, SheetFormat format) {
  SOFTBENCH_CHECK(!o.Problem()) << *o.Problem();
  const TagBitmap bitmap = Tag36h11Bitmap(o.id);
  const TagLayout l = LayOutTag(o, bitmap);
  const std::string title = fmt::format("AprilTag tag36h11, id {}", o.id);
  return RenderSheet(
      o.sheet.paper.width_mm, o.sheet.paper.height_mm, format, title,
      [&](cairo_t* cr) {
        Header(cr, o.sheet, title,
               fmt::format("Black border {:.1f} mm edge to edge: the plan's "
                           "calibration.tag size_mm.",
                           o.size_mm));
        // The cells, each black one a filled square; neighbours share exact
        // edges so no seam shows.
        const double cell = o.size_mm / bitmap.width_at_border;
        for (int row = 0; row < bitmap.total_width; ++row) {
          for (int col = 0; col < bitmap.total_width; ++col) {
            if (bitmap.IsWhite(row, col)) continue;
            cairo_rectangle(cr, l.left_mm + col * cell, l.top_mm + row * cell,
                            cell, cell);
          }
        }
        cairo_set_antialias(cr, CAIRO_ANTIALIAS_NONE);
        cairo_fill(cr);
        cairo_set_antialias(cr, CAIRO_ANTIALIAS_DEFAULT);
        // A light cut line around the white quiet zone, which must stay.
        cairo_set_source_rgb(cr, 0.6, 0.6, 0.6);
        cairo_set_line_width(cr, 0.2);
        const double dash = 1.5;
        cairo_set_dash(cr, &dash, 1, 0.0);
        cairo_rectangle(cr, l.left_mm - 0.1, l.top_mm - 0.1, l.quiet_mm + 0.2,
                        l.quiet_mm + 0.2);
        cairo_stroke(cr);
        cairo_set_dash(cr, nullptr, 0, 0.0);
        cairo_set_source_rgb(cr, 0, 0, 0);
        Text(cr, l.left_mm + l.quiet_mm / 2.0, l.top_mm + l.quiet_mm + 5.0,
             kSmallMm,
             "Cut on the dashed line, keeping the white border. Mount it flat "
             "with this side up: top = world +z, right = world +y.",
             Align::kCentre);
        CheckBar(cr, o.sheet.margin_mm, l.bar_y_mm, l.bar_mm, false);
        CheckBar(cr, o.sheet.paper.width_mm - o.sheet.margin_mm - kBarMm,
                 l.top_mm, l.bar_mm, true);
        const int ruler_mm =
            static_cast<int>(std::floor((o.sheet.paper.width_mm -
                                         2.0 * o.sheet.margin_mm - 6.0) /
                                        10.0) *
                             10.0);
        Ruler(cr, o.sheet.margin_mm + 3.0, l.ruler_y_mm, ruler_mm);
      });
}

std::string DrawCheckerboardSheet(const CheckerboardSheetOptions& o,
                                  SheetFormat format) {
  SOFTBENCH_CHECK(!o.Problem()) << *o.Problem();
  const BoardLayout l = LayOutBoard(o);
  const BoardOptions& b = o.board;
  const std::string title =
      fmt::format("Checkerboard, {} x {} inner corners, {:.1f} mm squares",
                  b.corners_x, b.corners_y, b.square_mm);
  return RenderSheet(l.page_w_mm, l.page_h_mm, format, title, [&](cairo_t* cr) {
    Header(cr, o.sheet, title,
           fmt::format("softbench calibrate-camera --board {}x{} "
                       "--square-mm {:.1f}   (keep it flat: glue it to "
                       "glass or board)",
                       b.corners_x, b.corners_y, b.square_mm));
    for (int row = 0; row <= b.corners_y; ++row) {
      for (int col = 0; col <= b.corners_x; ++col) {
        if ((row + col) % 2 != 0) continue;
        cairo_rectangle(cr, l.left_mm + col * b.square_mm,
                        l.top_mm + row * b.square_mm, b.square_mm, b.square_mm);
      }
    }
    cairo_set_antialias(cr, CAIRO_ANTIALIAS_NONE);
    cairo_fill(cr);
    cairo_set_antialias(cr, CAIRO_ANTIALIAS_DEFAULT);
    const double below = l.top_mm + l.height_mm + 6.0;
    const double bar =
        std::min(10.0 * b.square_mm, l.page_w_mm - 2.0 * o.sheet.margin_mm);
    CheckBar(cr, o.sheet.margin_mm, below + 2.0, bar, false);
    const double ruler_y = l.page_h_mm - o.sheet.margin_mm - kRulerMm + 2.0;
    if (ruler_y > below + 8.0) {
      const int ruler_mm = static_cast<int>(
          std::floor((l.page_w_mm - 2.0 * o.sheet.margin_mm - 6.0) / 10.0) *
          10.0);
      Ruler(cr, o.sheet.margin_mm + 3.0, ruler_y, ruler_mm);
    }
  });
}

std::string DrawDotSheet(const DotSheetOptions& o, SheetFormat format) {
  SOFTBENCH_CHECK(!o.Problem()) << *o.Problem();
  const SheetOptions& s = o.sheet;
  return RenderSheet(
      s.paper.width_mm, s.paper.height_mm, format, "Dot stickers",
      [&](cairo_t* cr) {
        Header(cr, s, "Dot stickers",
               "Stick each head's dots where the plan's layout_mm puts them; "
               "check printed colours with softbench tune.");
        double y = s.margin_mm + kHeaderMm;
        for (const DotGroup& g : o.groups) {
          Text(cr, s.margin_mm, y + 4.0, kTextMm,
               fmt::format("{}: {:.1f} mm dots, {} per head ({} printed)",
                           g.label, g.diameter_mm, g.dots_per_head,
                           g.dots_per_head * o.sets));
          const double pitch = DotPitchMm(g);
          const int per_row = DotsPerRow(s, g);
          cairo_set_source_rgb(cr, g.ink_bgr[2] / 255.0, g.ink_bgr[1] / 255.0,
                               g.ink_bgr[0] / 255.0);
          for (int i = 0; i < g.dots_per_head * o.sets; ++i) {
            const double cx =
                s.margin_mm + g.diameter_mm / 2.0 + (i % per_row) * pitch;
            const double cy =
                y + 7.0 + g.diameter_mm / 2.0 +
                // The row of dot i: integer division.
                static_cast<double>(
                    i / per_row) *  // NOLINT(bugprone-integer-division)
                    pitch;
            cairo_new_sub_path(cr);
            cairo_arc(cr, cx, cy, g.diameter_mm / 2.0, 0.0,
                      2.0 * std::numbers::pi);
          }
          cairo_fill(cr);
          cairo_set_source_rgb(cr, 0, 0, 0);
          y += DotGroupHeightMm(s, g, o.sets);
        }
        CheckBar(cr, s.margin_mm, y + 6.0, kDotCheckBarMm, false);
      });
}

}  // namespace softbench
