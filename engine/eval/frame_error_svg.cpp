#include "eval/frame_error_svg.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "eval/frame_error_csv.h"

namespace facesr {
namespace {

constexpr double kWidth = 960, kHeight = 480;
constexpr double kLeft = 80, kRight = 190, kTop = 56, kBottom = 64;

std::string xml_escape(const std::string& s) {
  std::string r;
  for (const char c : s) {
    switch (c) {
      case '&':
        r += "&amp;";
        break;
      case '<':
        r += "&lt;";
        break;
      case '>':
        r += "&gt;";
        break;
      case '"':
        r += "&quot;";
        break;
      case '\'':
        r += "&apos;";
        break;
      default:
        // Control characters are not allowed in XML 1.0 text.
        if (static_cast<unsigned char>(c) >= 0x20 || c == '\t') r += c;
    }
  }
  return r;
}

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f", v);
  return buf;
}

std::string tick_label(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", std::abs(v) < 1e-12 ? 0.0 : v);
  return buf;
}

std::string colour(const std::string& method, size_t other_index) {
  static const char* kPalette[] = {"#1f77b4", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b",
                                   "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"};
  if (method == "ours") return "#d62728";
  return kPalette[other_index % (sizeof kPalette / sizeof *kPalette)];
}

}  // namespace

double nice_tick_step(double range, int target) {
  if (!(range > 0) || target < 1) return 1;
  const double raw = range / target, p = std::pow(10.0, std::floor(std::log10(raw)));
  for (const double m : {1.0, 2.0, 5.0})
    if (m * p >= raw) return m * p;
  return 10 * p;
}

std::string frame_error_svg(const std::vector<FrameId>& frames, const std::vector<std::string>& methods,
                            const std::vector<std::vector<double>>& frame_means, const std::string& title) {
  check_frame_table(frames, methods, frame_means, "frame error plot");
  const size_t F = frames.size();
  const double pw = kWidth - kLeft - kRight, ph = kHeight - kTop - kBottom;
  double ymax = 0;
  for (const auto& col : frame_means)
    for (const double v : col) ymax = std::max(ymax, v);
  const double ystep = nice_tick_step(ymax > 0 ? ymax : 1, 6);
  ymax = ystep * std::max(1.0, std::ceil(ymax / ystep * 1.0001));
  const double xmax = std::max<double>(1, double(F - 1));
  auto X = [&](double f) { return kLeft + (F == 1 ? pw / 2 : pw * f / xmax); };
  auto Y = [&](double v) { return kTop + ph * (1 - std::max(0.0, v) / ymax); };

  std::ostringstream s;
  s << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
    << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << kWidth << "\" height=\"" << kHeight
    << "\" viewBox=\"0 0 " << kWidth << ' ' << kHeight << "\" font-family=\"sans-serif\" font-size=\"12\">\n"
    << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
    << "<text x=\"" << num(kLeft + pw / 2) << "\" y=\"28\" text-anchor=\"middle\" font-size=\"16\">"
    << xml_escape(title) << "</text>\n";

  // Grid and y ticks.
  s << "<g stroke=\"#e0e0e0\" stroke-width=\"1\">\n";
  // Ticks at whole multiples of the step: accumulating it would print 0.30000000000000004.
  const int yticks = int(std::lround(ymax / ystep));
  for (int t = 0; t <= yticks; ++t)
    s << "<line x1=\"" << num(kLeft) << "\" y1=\"" << num(Y(t * ystep)) << "\" x2=\"" << num(kLeft + pw) << "\" y2=\""
      << num(Y(t * ystep)) << "\"/>\n";
  s << "</g>\n<g text-anchor=\"end\">\n";
  for (int t = 0; t <= yticks; ++t)
    s << "<text x=\"" << num(kLeft - 8) << "\" y=\"" << num(Y(t * ystep) + 4) << "\">" << tick_label(t * ystep)
      << "</text>\n";
  s << "</g>\n";

  // x ticks: whole frame indices.
  const double xstep = std::max(1.0, nice_tick_step(xmax, 8));
  s << "<g text-anchor=\"middle\">\n";
  for (double f = 0; f <= xmax + 1e-9 && f < double(F); f += xstep)
    s << "<line x1=\"" << num(X(f)) << "\" y1=\"" << num(kTop + ph) << "\" x2=\"" << num(X(f)) << "\" y2=\""
      << num(kTop + ph + 5) << "\" stroke=\"black\"/>\n<text x=\"" << num(X(f)) << "\" y=\"" << num(kTop + ph + 19)
      << "\">" << tick_label(f) << "</text>\n";
  s << "</g>\n";

  // Sequence spans: a dashed separator where each sequence after the first
  // starts, and its name over the span.
  for (size_t f = 0; f < F;) {
    size_t e = f;
    while (e < F && frames[e].sequence == frames[f].sequence) ++e;
    if (f > 0)
      s << "<line x1=\"" << num(X(double(f) - 0.5)) << "\" y1=\"" << num(kTop) << "\" x2=\"" << num(X(double(f) - 0.5))
        << "\" y2=\"" << num(kTop + ph) << "\" stroke=\"#909090\" stroke-dasharray=\"4 3\"/>\n";
    s << "<text x=\"" << num(X(0.5 * double(f + e - 1))) << "\" y=\"" << num(kTop - 6)
      << "\" text-anchor=\"middle\" fill=\"#606060\">" << xml_escape(frames[f].sequence) << "</text>\n";
    f = e;
  }

  // Axes and their labels.
  s << "<path d=\"M" << num(kLeft) << ' ' << num(kTop) << " V" << num(kTop + ph) << " H" << num(kLeft + pw)
    << "\" fill=\"none\" stroke=\"black\"/>\n"
    << "<text x=\"" << num(kLeft + pw / 2) << "\" y=\"" << num(kHeight - 18)
    << "\" text-anchor=\"middle\">test frame (index across the test sequences)</text>\n"
    << "<text transform=\"translate(22 " << num(kTop + ph / 2)
    << ") rotate(-90)\" text-anchor=\"middle\">mean per-vertex error (cm)</text>\n";

  // One polyline per method, markers when the frames are few enough to see them.
  size_t others = 0;
  std::vector<std::string> colours;
  for (const std::string& m : methods) colours.push_back(colour(m, m == "ours" ? 0 : others++));
  for (size_t m = 0; m < methods.size(); ++m) {
    s << "<polyline fill=\"none\" stroke=\"" << colours[m] << "\" stroke-width=\"1.6\" points=\"";
    for (size_t f = 0; f < F; ++f) s << (f ? " " : "") << num(X(double(f))) << ',' << num(Y(frame_means[m][f]));
    s << "\"><title>" << xml_escape(methods[m]) << "</title></polyline>\n";
    if (F <= 60)
      for (size_t f = 0; f < F; ++f)
        s << "<circle cx=\"" << num(X(double(f))) << "\" cy=\"" << num(Y(frame_means[m][f])) << "\" r=\"2.2\" fill=\""
          << colours[m] << "\"/>\n";
  }

  // Legend to the right of the plot.
  const double lx = kLeft + pw + 18;
  s << "<g>\n";
  for (size_t m = 0; m < methods.size(); ++m) {
    const double ly = kTop + 10 + 20 * double(m);
    s << "<line x1=\"" << num(lx) << "\" y1=\"" << num(ly) << "\" x2=\"" << num(lx + 24) << "\" y2=\"" << num(ly)
      << "\" stroke=\"" << colours[m] << "\" stroke-width=\"2.5\"/>\n<text x=\"" << num(lx + 30) << "\" y=\""
      << num(ly + 4) << "\">" << xml_escape(methods[m]) << "</text>\n";
  }
  s << "</g>\n</svg>\n";
  return s.str();
}

void write_frame_error_svg(const std::string& path, const std::vector<FrameId>& frames,
                           const std::vector<std::string>& methods, const std::vector<std::vector<double>>& frame_means,
                           const std::string& title) {
  const std::string svg = frame_error_svg(frames, methods, frame_means, title);
  write_file_atomically(path, [&](std::ostream& out) { out << svg; });
}

}  // namespace facesr
