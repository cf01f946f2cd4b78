// The static SVG of a column's WV plot (PATH.svg beside the report), for people who paste
// images. A trivial polyline plot drawn here (html_report.h says why not by Vega): log-log
// axes with decade ticks and grid, each WV with its CI band (polygon) and points, the
// model's WV (solid) and its components (dashed), a legend. Colours as in the Vega plot.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "html_report_detail.h"

namespace gmwm::report {

namespace {

using detail::html_escape;

constexpr std::array<const char*, 10> kPalette = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd",
                                                  "#8c564b", "#e377c2", "#17becf", "#bcbd22", "#7f7f7f"};
constexpr double kWidth = 860, kHeight = 480;
constexpr double kLeft = 86, kRight = 250, kTop = 40, kBottom = 56;

std::string f2(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f", x);
  return buf;
}

struct Axis {
  double lo = -1, hi = 1;  // log10
  double a = 0, b = 1;     // pixel range
  double px(double v) const { return a + (std::log10(v) - lo) / (hi - lo) * (b - a); }
};

Axis log_axis(const std::vector<double>& values, double a, double b) {
  Axis ax;
  ax.a = a;
  ax.b = b;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const double v : values)
    if (std::isfinite(v) && v > 0.0) {
      lo = std::min(lo, std::log10(v));
      hi = std::max(hi, std::log10(v));
    }
  if (!std::isfinite(lo)) return ax;
  if (hi - lo < 1e-9) {
    lo -= 0.5;
    hi += 0.5;
  }
  const double pad = 0.05 * (hi - lo);
  ax.lo = lo - pad;
  ax.hi = hi + pad;
  return ax;
}

std::string decade_label(int e) {
  static const char* plain[] = {"0.01", "0.1", "1", "10", "100", "1000"};
  if (e >= -2 && e <= 3) return plain[e + 2];
  return "1e" + std::to_string(e);
}

}  // namespace

std::string render_wv_svg(const ReportColumn& c) {
  std::vector<detail::WvSeries> est;
  for (const auto& w : c.wvs) est.push_back(detail::wv_series(w, c));
  std::vector<detail::Curve> curves;
  std::string title = c.name + ": wavelet variance";
  if (const FitResult* f = detail::shown_model(c); f && !c.wvs.empty()) {
    curves = detail::model_curves(f->model, f->theta, detail::model_tau(c), detail::tau_scale(c),
                                  "model " + f->model.to_string(), true);
    title += " and " + std::string(c.selection ? "chosen model " : "fitted model ") + f->model.to_string();
  }
  std::vector<double> xs, ys;
  for (const auto& s : est)
    for (const auto& p : s.points) {
      xs.push_back(p.tau);
      ys.insert(ys.end(), {p.wv, p.lo, p.hi});
    }
  for (const auto& cv : curves) {
    xs.insert(xs.end(), cv.tau.begin(), cv.tau.end());
    ys.insert(ys.end(), cv.value.begin(), cv.value.end());
  }
  const Axis x = log_axis(xs, kLeft, kWidth - kRight);
  const Axis y = log_axis(ys, kHeight - kBottom, kTop);

  std::ostringstream os;
  os << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << kWidth << "\" height=\"" << kHeight
     << "\" viewBox=\"0 0 " << kWidth << " " << kHeight
     << "\" font-family=\"Helvetica, Arial, sans-serif\" font-size=\"12\">\n"
     << "<rect width=\"100%\" height=\"100%\" fill=\"#ffffff\"/>\n"
     << "<text x=\"" << kLeft << "\" y=\"22\" font-size=\"14\" font-weight=\"bold\">" << html_escape(title)
     << "</text>\n";
  // Grid and decade ticks.
  os << "<g stroke=\"#e3e3e3\" stroke-width=\"1\">\n";
  for (int e = static_cast<int>(std::ceil(x.lo)); e <= static_cast<int>(std::floor(x.hi)); ++e)
    os << "<line x1=\"" << f2(x.px(std::pow(10.0, e))) << "\" y1=\"" << kTop << "\" x2=\""
       << f2(x.px(std::pow(10.0, e))) << "\" y2=\"" << kHeight - kBottom << "\"/>\n";
  for (int e = static_cast<int>(std::ceil(y.lo)); e <= static_cast<int>(std::floor(y.hi)); ++e)
    os << "<line x1=\"" << kLeft << "\" y1=\"" << f2(y.px(std::pow(10.0, e))) << "\" x2=\"" << kWidth - kRight
       << "\" y2=\"" << f2(y.px(std::pow(10.0, e))) << "\"/>\n";
  os << "</g>\n<g fill=\"#333333\">\n";
  for (int e = static_cast<int>(std::ceil(x.lo)); e <= static_cast<int>(std::floor(x.hi)); ++e)
    os << "<text x=\"" << f2(x.px(std::pow(10.0, e))) << "\" y=\"" << kHeight - kBottom + 16
       << "\" text-anchor=\"middle\">" << decade_label(e) << "</text>\n";
  for (int e = static_cast<int>(std::ceil(y.lo)); e <= static_cast<int>(std::floor(y.hi)); ++e)
    os << "<text x=\"" << kLeft - 6 << "\" y=\"" << f2(y.px(std::pow(10.0, e)) + 4) << "\" text-anchor=\"end\">"
       << decade_label(e) << "</text>\n";
  os << "<text x=\"" << f2((kLeft + kWidth - kRight) / 2) << "\" y=\"" << kHeight - 14
     << "\" text-anchor=\"middle\">tau [" << html_escape(detail::tau_unit(c)) << "]</text>\n"
     << "<text transform=\"translate(20," << f2((kTop + kHeight - kBottom) / 2)
     << ") rotate(-90)\" text-anchor=\"middle\">wavelet variance nu^2 [(" << html_escape(detail::data_unit(c))
     << ")^2]</text>\n</g>\n";
  os << "<rect x=\"" << kLeft << "\" y=\"" << kTop << "\" width=\"" << kWidth - kRight - kLeft << "\" height=\""
     << kHeight - kBottom - kTop << "\" fill=\"none\" stroke=\"#888888\"/>\n";
  os << "<clipPath id=\"plot\"><rect x=\"" << kLeft << "\" y=\"" << kTop << "\" width=\"" << kWidth - kRight - kLeft
     << "\" height=\"" << kHeight - kBottom - kTop << "\"/></clipPath>\n<g clip-path=\"url(#plot)\" fill=\"none\">\n";
  std::size_t colour = 0;
  std::vector<std::pair<std::string, std::pair<std::string, bool>>> legend;  // name, colour, dashed
  for (const auto& s : est) {
    const char* col = kPalette[colour++ % kPalette.size()];
    legend.push_back({s.name, {col, false}});
    std::string upper, lower;
    for (const auto& p : s.points)
      if (p.lo > 0.0 && p.hi > 0.0) {
        upper += f2(x.px(p.tau)) + "," + f2(y.px(p.hi)) + " ";
        lower = f2(x.px(p.tau)) + "," + f2(y.px(p.lo)) + " " + lower;
      }
    if (!upper.empty())
      os << "<polygon points=\"" << upper << lower << "\" fill=\"" << col
         << "\" fill-opacity=\"0.18\" stroke=\"none\"/>\n";
    std::string line;
    for (const auto& p : s.points) line += f2(x.px(p.tau)) + "," + f2(y.px(p.wv)) + " ";
    os << "<polyline points=\"" << line << "\" stroke=\"" << col << "\" stroke-width=\"2\"/>\n";
    for (const auto& p : s.points)
      os << "<circle cx=\"" << f2(x.px(p.tau)) << "\" cy=\"" << f2(y.px(p.wv)) << "\" r=\"2.6\" fill=\"" << col
         << "\"/>\n";
  }
  for (const auto& cv : curves) {
    const char* col = kPalette[colour++ % kPalette.size()];
    legend.push_back({cv.name, {col, cv.dashed}});
    std::string line;
    for (std::size_t j = 0; j < cv.tau.size(); ++j) line += f2(x.px(cv.tau[j])) + "," + f2(y.px(cv.value[j])) + " ";
    os << "<polyline points=\"" << line << "\" stroke=\"" << col << "\" stroke-width=\"" << (cv.dashed ? "1.5" : "2.5")
       << "\"" << (cv.dashed ? " stroke-dasharray=\"6,4\"" : "") << "/>\n";
  }
  os << "</g>\n<g>\n";
  double ly = kTop + 8;
  const double lx = kWidth - kRight + 16;
  for (const auto& [name, style] : legend) {
    os << "<line x1=\"" << lx << "\" y1=\"" << f2(ly) << "\" x2=\"" << lx + 24 << "\" y2=\"" << f2(ly) << "\" stroke=\""
       << style.first << "\" stroke-width=\"2.5\"" << (style.second ? " stroke-dasharray=\"6,4\"" : "") << "/>\n"
       << "<text x=\"" << lx + 30 << "\" y=\"" << f2(ly + 4) << "\">" << html_escape(name) << "</text>\n";
    ly += 18;
  }
  if (!c.wvs.empty())
    os << "<text x=\"" << lx << "\" y=\"" << f2(ly + 10)
       << "\" fill=\"#57606a\" font-size=\"11\">bands: " << detail::num(100.0 * (1.0 - c.wvs.front().alpha), 3)
       << "% CI</text>\n";
  os << "</g>\n</svg>\n";
  return os.str();
}

}  // namespace gmwm::report
