// The report's Vega 5 specs (plain Vega: vega-lite is not packaged in Debian 12). Every
// log-log plot pans with the mouse, zooms with the wheel about the pointer (in log10
// space) and resets on double-click; hovering a point shows its values (Vega's default
// tooltip handler: the SVG title).

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>

#include "html_report_detail.h"

namespace gmwm::report::detail {

namespace {

// A replicate's legend label: its file name without the folder (the column is the axis's).
std::string source_label(const std::string& source) {
  const auto colon = source.rfind(':');
  const std::string file = colon == std::string::npos ? source : source.substr(0, colon);
  const auto slash = file.find_last_of('/');
  return slash == std::string::npos ? file : file.substr(slash + 1);
}

// Series colours: the WV estimates first, then the model, then its components. The static
// SVG (html_report_svg.cc) uses the same order.
constexpr std::array<const char*, 10> kPalette = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd",
                                                  "#8c564b", "#e377c2", "#17becf", "#bcbd22", "#7f7f7f"};
constexpr const char* kReferenceColour = "#9a9a9a";
constexpr int kPlotWidth = 560, kPlotHeight = 340;

Json number(double x) { return json_number(x); }

struct LogLog {
  std::string title, x_title, y_title, tau_unit;
  std::string value_name = "WV";  ///< the y quantity in tooltips
  std::vector<WvSeries> estimates;
  std::vector<Curve> curves;
  std::string reference_name;                    ///< empty: no reference band
  std::vector<std::array<double, 3>> reference;  ///< tau, low, high
  /// Where a fit (or a gap comparison) that left the finer levels out starts (axis units,
  /// between its first level and the one below): the scales below are shaded and labelled
  /// `fitted_label`. NaN: every level used.
  double fitted_from = std::numeric_limits<double>::quiet_NaN();
  std::string fitted_label = "not fitted";
};

// A shade over the scales below `edge` (axis units) and its label ("not fitted"): the levels
// a fit (or a gap comparison) from a first level above 1 left out.
Json not_fitted_marks(double edge_tau, const std::string& text) {
  const Json edge = {{"scale", "x"}, {"value", edge_tau}};
  Json shade = {{"type", "rect"},
                {"clip", true},
                {"encode",
                 {{"update",
                   {{"x", {{"value", 0}}},
                    {"x2", edge},
                    {"y", {{"value", 0}}},
                    {"y2", {{"signal", "height"}}},
                    {"fill", {{"value", kReferenceColour}}},
                    {"fillOpacity", {{"value", 0.18}}}}}}}};
  Json label = {{"type", "text"},
                {"clip", true},
                {"encode",
                 {{"update",
                   {{"x", edge},
                    {"dx", {{"value", -4}}},
                    {"y", {{"value", 4}}},
                    {"align", {{"value", "right"}}},
                    {"baseline", {{"value", "top"}}},
                    {"fill", {{"value", "#555"}}},
                    {"text", {{"value", text}}}}}}}};
  return Json::array({std::move(shade), std::move(label)});
}

// log10 of the range of everything drawn, padded by 5% of its span on each side.
std::array<double, 2> padded_log_range(std::vector<double> v) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const double x : v)
    if (std::isfinite(x) && x > 0.0) {
      lo = std::min(lo, std::log10(x));
      hi = std::max(hi, std::log10(x));
    }
  if (!std::isfinite(lo)) return {-1.0, 1.0};
  if (hi - lo < 1e-9) return {lo - 0.5, hi + 0.5};
  const double pad = 0.05 * (hi - lo);
  return {lo - pad, hi + pad};
}

// Pan (drag), zoom (wheel, about the pointer) and reset (double-click) of two log10
// domains xl and yl; the scales' domains are 10^xl and 10^yl.
Json zoom_signals(const std::array<double, 2>& x, const std::array<double, 2>& y) {
  const Json x0 = {x[0], x[1]}, y0 = {y[0], y[1]};
  Json s = Json::array();
  s.push_back(
      {{"name", "down"},
       {"value", nullptr},
       {"on",
        {{{"events", "touchend"}, {"update", "null"}}, {{"events", "mousedown, touchstart"}, {"update", "xy()"}}}}});
  s.push_back({{"name", "xcur"},
               {"value", nullptr},
               {"on", {{{"events", "mousedown, touchstart, touchend"}, {"update", "slice(xl)"}}}}});
  s.push_back({{"name", "ycur"},
               {"value", nullptr},
               {"on", {{{"events", "mousedown, touchstart, touchend"}, {"update", "slice(yl)"}}}}});
  s.push_back({{"name", "delta"},
               {"value", {0, 0}},
               {"on",
                {{{"events",
                   {{{"source", "window"},
                     {"type", "mousemove"},
                     {"consume", true},
                     {"between", {{{"type", "mousedown"}}, {{"source", "window"}, {"type", "mouseup"}}}}},
                    {{"type", "touchmove"}, {"consume", true}, {"filter", "event.touches.length === 1"}}}},
                  {"update", "down ? [down[0] - x(), y() - down[1]] : [0, 0]"}}}}});
  s.push_back(
      {{"name", "anchor"},
       {"value", {0, 0}},
       {"on", {{{"events", "wheel"}, {"update", "[log(invert('x', x())) / LN10, log(invert('y', y())) / LN10]"}}}}});
  s.push_back(
      {{"name", "zoom"},
       {"value", 1},
       {"on",
        {{{"events", "wheel!"}, {"force", true}, {"update", "pow(1.001, event.deltaY * pow(16, event.deltaMode))"}}}}});
  s.push_back({{"name", "xl"},
               {"value", x0},
               {"on",
                {{{"events", {{"signal", "delta"}}},
                  {"update", "[xcur[0] + span(xcur) * delta[0] / width, xcur[1] + span(xcur) * delta[0] / width]"}},
                 {{"events", {{"signal", "zoom"}}},
                  {"update", "[anchor[0] + (xl[0] - anchor[0]) * zoom, anchor[0] + (xl[1] - anchor[0]) * zoom]"}},
                 {{"events", "dblclick"}, {"update", x0.dump()}}}}});
  s.push_back({{"name", "yl"},
               {"value", y0},
               {"on",
                {{{"events", {{"signal", "delta"}}},
                  {"update", "[ycur[0] + span(ycur) * delta[1] / height, ycur[1] + span(ycur) * delta[1] / height]"}},
                 {{"events", {{"signal", "zoom"}}},
                  {"update", "[anchor[1] + (yl[0] - anchor[1]) * zoom, anchor[1] + (yl[1] - anchor[1]) * zoom]"}},
                 {{"events", "dblclick"}, {"update", y0.dump()}}}}});
  return s;
}

Json xy(const char* x_field, const char* y_field) {
  return {{"x", {{"scale", "x"}, {"field", x_field}}}, {"y", {{"scale", "y"}, {"field", y_field}}}};
}

// A group of marks faceted by "series" over `data`, as large as the plot (so that the
// clipped marks inside see the plot's bounds).
Json facet_group(const std::string& name, const std::string& data, Json marks) {
  return {{"type", "group"},
          {"from", {{"facet", {{"name", name}, {"data", data}, {"groupby", "series"}}}}},
          {"encode", {{"update", {{"width", {{"signal", "width"}}}, {"height", {{"signal", "height"}}}}}}},
          {"marks", std::move(marks)}};
}

Json loglog_spec(const LogLog& p) {
  Json points = Json::array(), curves = Json::array(), reference = Json::array();
  std::vector<double> xs, ys;
  Json domain = Json::array(), range = Json::array();
  std::size_t colour = 0;
  auto add_series = [&](const std::string& name, const char* fixed = nullptr) {
    domain.push_back(name);
    range.push_back(fixed ? fixed : kPalette[colour++ % kPalette.size()]);
  };
  for (const auto& s : p.estimates) {
    add_series(s.name);
    for (const auto& q : s.points) {
      points.push_back({{"series", s.name},
                        {"level", q.level},
                        {"tau", q.tau},
                        {"wv", q.wv},
                        {"lo", number(q.lo)},
                        {"hi", number(q.hi)}});
      xs.push_back(q.tau);
      ys.insert(ys.end(), {q.wv, q.lo, q.hi});
    }
  }
  if (!p.reference_name.empty()) {
    add_series(p.reference_name, kReferenceColour);
    for (const auto& r : p.reference)
      if (r[1] > 0.0 && r[2] > 0.0 && std::isfinite(r[1]) && std::isfinite(r[2])) {
        reference.push_back({{"tau", r[0]}, {"lo", r[1]}, {"hi", r[2]}});
        xs.push_back(r[0]);
        ys.insert(ys.end(), {r[1], r[2]});
      }
  }
  bool any_dashed = false;
  for (const auto& c : p.curves) {
    add_series(c.name);
    any_dashed = any_dashed || c.dashed;
    for (std::size_t j = 0; j < c.tau.size(); ++j) {
      curves.push_back({{"series", c.name}, {"dashed", c.dashed}, {"tau", c.tau[j]}, {"v", c.value[j]}});
      xs.push_back(c.tau[j]);
      ys.push_back(c.value[j]);
    }
  }
  const auto xr = padded_log_range(xs), yr = padded_log_range(ys);

  Json spec = {{"$schema", "https://vega.github.io/schema/vega/v5.json"},
               {"width", kPlotWidth},
               {"height", kPlotHeight},
               {"padding", 5},
               {"title", {{"text", p.title}, {"anchor", "start"}, {"fontSize", 13}}}};
  Json signals = zoom_signals(xr, yr);
  signals.push_back({{"name", "show_ci"}, {"value", true}, {"bind", {{"input", "checkbox"}, {"name", "CI bands "}}}});
  if (any_dashed)
    signals.push_back(
        {{"name", "show_components"}, {"value", true}, {"bind", {{"input", "checkbox"}, {"name", "components "}}}});
  else
    signals.push_back({{"name", "show_components"}, {"value", true}});
  spec["signals"] = std::move(signals);
  spec["data"] = {{{"name", "points"}, {"values", std::move(points)}},
                  {{"name", "bands"},
                   {"source", "points"},
                   {"transform", {{{"type", "filter"}, {"expr", "datum.lo > 0 && datum.hi > 0"}}}}},
                  {{"name", "curves"}, {"values", std::move(curves)}},
                  {{"name", "reference"}, {"values", std::move(reference)}}};
  spec["scales"] = {
      {{"name", "x"},
       {"type", "log"},
       {"domain", {{"signal", "[pow(10, xl[0]), pow(10, xl[1])]"}}},
       {"range", "width"},
       {"zero", false}},
      {{"name", "y"},
       {"type", "log"},
       {"domain", {{"signal", "[pow(10, yl[0]), pow(10, yl[1])]"}}},
       {"range", "height"},
       {"zero", false}},
      {{"name", "color"}, {"type", "ordinal"}, {"domain", std::move(domain)}, {"range", std::move(range)}}};
  spec["axes"] = {{{"orient", "bottom"},
                   {"scale", "x"},
                   {"title", p.x_title},
                   {"grid", true},
                   {"gridOpacity", 0.35},
                   {"labelOverlap", true}},
                  {{"orient", "left"},
                   {"scale", "y"},
                   {"title", p.y_title},
                   {"grid", true},
                   {"gridOpacity", 0.35},
                   {"format", ".1e"},
                   {"labelOverlap", true}}};
  spec["legends"] = {
      {{"stroke", "color"}, {"title", "series"}, {"orient", "right"}, {"symbolType", "stroke"}, {"labelLimit", 260}}};

  const std::string tip_point = "{'series': datum.series, 'level': datum.level, 'tau [" + p.tau_unit +
                                "]': format(datum.tau, '.4~g'), 'WV': format(datum.wv, '.4~e'), 'CI': (datum.lo > 0 ? "
                                "format(datum.lo, '.3~e') + ' to ' + "
                                "format(datum.hi, '.3~e') : 'n/a')}";
  const std::string tip_curve = "{'series': datum.series, 'tau [" + p.tau_unit + "]': format(datum.tau, '.4~g'), '" +
                                p.value_name + "': format(datum.v, '.4~e')}";
  Json marks = std::isfinite(p.fitted_from) ? not_fitted_marks(p.fitted_from, p.fitted_label) : Json::array();
  if (!p.reference_name.empty()) {
    Json enc = xy("tau", "lo");
    enc["y2"] = {{"scale", "y"}, {"field", "hi"}};
    enc["fill"] = {{"value", kReferenceColour}};
    enc["fillOpacity"] = {{"value", 0.3}};
    marks.push_back({{"type", "area"},
                     {"from", {{"data", "reference"}}},
                     {"clip", true},
                     {"sort", {{"field", "datum.tau"}}},
                     {"encode", {{"update", enc}}}});
  }
  {
    Json enc = xy("tau", "lo");
    enc["y2"] = {{"scale", "y"}, {"field", "hi"}};
    enc["fill"] = {{"scale", "color"}, {"field", "series"}};
    enc["fillOpacity"] = {{"signal", "show_ci ? 0.18 : 0"}};
    marks.push_back(facet_group("band_facet", "bands",
                                {{{"type", "area"},
                                  {"from", {{"data", "band_facet"}}},
                                  {"clip", true},
                                  {"sort", {{"field", "datum.tau"}}},
                                  {"encode", {{"update", enc}}}}}));
  }
  {
    Json line = xy("tau", "wv");
    line["stroke"] = {{"scale", "color"}, {"field", "series"}};
    line["strokeWidth"] = {{"value", 2}};
    Json sym = xy("tau", "wv");
    sym["fill"] = {{"scale", "color"}, {"field", "series"}};
    sym["size"] = {{"value", 30}};
    sym["tooltip"] = {{"signal", tip_point}};
    marks.push_back(facet_group("point_facet", "points",
                                {{{"type", "line"},
                                  {"from", {{"data", "point_facet"}}},
                                  {"clip", true},
                                  {"sort", {{"field", "datum.tau"}}},
                                  {"encode", {{"update", line}}}},
                                 {{"type", "symbol"},
                                  {"from", {{"data", "point_facet"}}},
                                  {"clip", true},
                                  {"encode", {{"update", sym}, {"hover", {{"size", {{"value", 110}}}}}}}}}));
  }
  {
    Json line = xy("tau", "v");
    line["stroke"] = {{"scale", "color"}, {"field", "series"}};
    line["strokeWidth"] = {{"signal", "datum.dashed ? 1.5 : 2.5"}};
    line["strokeDash"] = {{"signal", "datum.dashed ? [6, 4] : [1, 0]"}};
    line["strokeOpacity"] = {{"signal", "datum.dashed && !show_components ? 0 : 1"}};
    Json sym = xy("tau", "v");
    sym["fill"] = {{"scale", "color"}, {"field", "series"}};
    sym["size"] = {{"value", 14}};
    sym["opacity"] = {{"signal", "datum.dashed && !show_components ? 0 : 1"}};
    sym["tooltip"] = {{"signal", tip_curve}};
    marks.push_back(facet_group("curve_facet", "curves",
                                {{{"type", "line"},
                                  {"from", {{"data", "curve_facet"}}},
                                  {"clip", true},
                                  {"sort", {{"field", "datum.tau"}}},
                                  {"encode", {{"update", line}}}},
                                 {{"type", "symbol"},
                                  {"from", {{"data", "curve_facet"}}},
                                  {"clip", true},
                                  {"encode", {{"update", sym}, {"hover", {{"size", {{"value", 80}}}}}}}}}));
  }
  spec["marks"] = std::move(marks);
  return spec;
}

std::string wv_axis_title(const ReportColumn& c) { return "wavelet variance nu^2 [(" + data_unit(c) + ")^2]"; }

std::string tau_axis_title(const ReportColumn& c) { return "tau [" + tau_unit(c) + "]"; }

double max_abs(const std::vector<double>& v, double floor) {
  double m = floor;
  for (const double x : v)
    if (std::isfinite(x)) m = std::max(m, std::abs(x));
  return m;
}

}  // namespace

Json wv_plot_spec(const ReportColumn& c) {
  LogLog p;
  p.x_title = tau_axis_title(c);
  p.tau_unit = tau_unit(c);
  p.y_title = wv_axis_title(c);
  for (std::size_t k = 0; k < c.wvs.size(); ++k) {
    p.estimates.push_back(wv_series(c.wvs[k], c));
    if (c.replicates && k < c.replicates->sources.size())
      p.estimates.back().name = "replicate " + std::to_string(k + 1) + ": " + source_label(c.replicates->sources[k]);
  }
  std::string title = c.name + ": wavelet variance";
  if (c.replicates) title += " of " + std::to_string(c.wvs.size()) + " replicates";
  if (const FitResult* f = shown_model(c); f && !c.wvs.empty()) {
    p.curves = model_curves(f->model, f->theta, model_tau(c), tau_scale(c),
                            (c.replicates ? "joint model " : "model ") + f->model.to_string(), true);
    // A fit from a level above the first (--first-level): its start, half a level below.
    if (!c.replicates && !f->misfits.empty() && f->misfits.front().level > 1)
      p.fitted_from = tau_scale(c) * f->misfits.front().tau / std::sqrt(2.0);
    title += " and " +
             std::string(c.replicates  ? (c.replicates->selection ? "recommended joint model " : "joint model ")
                         : c.selection ? "chosen model "
                                       : "fitted model ") +
             f->model.to_string();
  }
  if (!c.wvs.empty()) {
    for (const ReportColumn::Reference& r : c.references) {
      std::vector<Curve> curve = model_curves(r.model, r.theta, model_tau(c), tau_scale(c), r.name, false);
      p.curves.insert(p.curves.end(), curve.begin(), curve.end());
    }
    if (!c.references.empty()) title += c.references.size() == 1 ? ", a reference model" : ", reference models";
    title += " (" + num(100.0 * (1.0 - c.wvs.front().alpha), 3) + "% CI)";
  }
  p.title = title;
  return loglog_spec(p);
}

Json adev_plot_spec(const ReportColumn& c) {
  const FigureReport& f = *c.allan;
  LogLog p;
  p.value_name = "ADEV";
  p.tau_unit = "s";
  p.x_title = "tau [s]";
  p.y_title = "Allan deviation [" + data_unit(c) + "]";
  WvSeries data;
  data.name = "data (overlapping ADEV)";
  for (std::size_t i = 0; i < f.adev.size(); ++i) {
    if (!(f.adev.adev[i] > 0.0)) continue;
    const double lo = f.adev.ci_low[i] > 0.0 ? f.adev.ci_low[i] : NAN,
                 hi = f.adev.ci_high[i] > 0.0 ? f.adev.ci_high[i] : NAN;
    data.points.push_back({static_cast<int>(f.adev.m[i]), f.adev.tau[i], f.adev.adev[i], lo, hi});
  }
  p.estimates.push_back(std::move(data));
  const std::vector<double>& tau = f.adev.tau;
  if (f.model_adev.size() == tau.size()) {
    Curve m;
    m.name = "model";
    for (std::size_t i = 0; i < tau.size(); ++i)
      if (f.model_adev[i] > 0.0) {
        m.tau.push_back(tau[i]);
        m.value.push_back(f.model_adev[i]);
      }
    p.curves.push_back(std::move(m));
  }
  // Reference models (html_report.h, ReportColumn::references): their Allan deviation at the
  // data's averaging times, as in the WV plot.
  for (const ReportColumn::Reference& r : c.references) {
    const std::vector<double> adev = model_allan_deviation(r.model, r.theta, f.adev.m);
    Curve ref;
    ref.name = r.name;
    for (std::size_t i = 0; i < tau.size() && i < adev.size(); ++i)
      if (adev[i] > 0.0 && std::isfinite(adev[i])) {
        ref.tau.push_back(tau[i]);
        ref.value.push_back(adev[i]);
      }
    if (!ref.tau.empty()) p.curves.push_back(std::move(ref));
  }
  // The IEEE 952 guides through the figures used, dashed, over the data's range.
  // Guides stay within a decade of the data's range, so they do not stretch the axis.
  double lo = INFINITY, hi = 0.0;
  for (const double a : f.adev.adev)
    if (a > 0.0) lo = std::min(lo, a), hi = std::max(hi, a);
  auto guide = [&](const std::string& name, const std::function<double(double)>& y) {
    Curve g;
    g.name = name;
    g.dashed = true;
    for (const double t : tau) {
      const double v = y(t);
      if (!(v >= lo / 10.0 && v <= hi * 10.0)) continue;
      g.tau.push_back(t);
      g.value.push_back(v);
    }
    if (!g.tau.empty()) p.curves.push_back(std::move(g));
  };
  const double N = f.chosen.white.figure.value, K = f.chosen.walk.figure.value, B = f.chosen.instability.figure.value;
  // A figure the curves only bound is labelled as a bound, as the tables say it ("K < 4.1e-05").
  auto is = [](const ChosenFigure& x) -> std::string {
    return x.source == FigureSource::kBound || x.figure.status == ReadoffStatus::kBound ? " < " : " = ";
  };
  if (N > 0.0)
    guide("N" + is(f.chosen.white) + num(N, 4) + " (-1/2 slope)", [N](double t) { return N / std::sqrt(t); });
  if (K > 0.0)
    guide("K" + is(f.chosen.walk) + num(K, 4) + " (+1/2 slope)", [K](double t) { return K * std::sqrt(t / 3.0); });
  if (B > 0.0)
    guide("0.664 B, B" + is(f.chosen.instability) + num(B, 4), [B](double) { return kBiasInstabilityFactor * B; });
  // Q and R (IEEE 952: ADEV = sqrt(3) Q / tau, R tau / sqrt(2)).
  const double Q = f.chosen.quantization.figure.value, R = f.chosen.ramp.figure.value;
  if (Q > 0.0)
    guide("Q" + is(f.chosen.quantization) + num(Q, 4) + " (-1 slope)",
          [Q](double t) { return std::sqrt(3.0) * Q / t; });
  if (R > 0.0)
    guide("R" + is(f.chosen.ramp) + num(R, 4) + " (+1 slope)", [R](double t) { return R * t / std::sqrt(2.0); });
  p.title = c.name + ": Allan deviation" + (f.model_adev.empty() ? "" : " and the model's") + " (" +
            num(100.0 * (1.0 - f.adev.alpha), 3) + "% CI), IEEE 952 guides";
  return loglog_spec(p);
}

Json gap_curves_spec(const ReportColumn& c) {
  LogLog p;
  p.x_title = tau_axis_title(c);
  p.tau_unit = tau_unit(c);
  p.y_title = wv_axis_title(c);
  const gap::GapResult& g = *c.gap;
  const double scale = tau_scale(c);
  if (!c.wvs.empty()) p.estimates.push_back(wv_series(c.wvs.front(), c));
  p.reference_name = "baseline reference band";
  std::vector<double> tau;
  for (const auto& l : g.levels) {
    p.reference.push_back({l.tau * scale, l.ref_low, l.ref_high});
    tau.push_back(l.tau);
  }
  if (g.first_level > 1 && !tau.empty()) {  // the finer levels shown, not compared
    p.fitted_from = scale * tau.front() / std::sqrt(2.0);
    p.fitted_label = "not compared";
  }
  auto base = model_curves(g.baseline, g.baseline_theta, tau, scale, "baseline " + g.baseline.to_string(), false);
  p.curves.insert(p.curves.end(), base.begin(), base.end());
  if (!g.steps.empty()) {
    auto fin = model_curves(g.final_model, g.final_theta, tau, scale, "final " + g.final_model.to_string(), false);
    p.curves.insert(p.curves.end(), fin.begin(), fin.end());
  }
  p.title = c.name + ": before/after (data, baseline, final model)";
  return loglog_spec(p);
}

Json gap_levels_spec(const ReportData& d) {
  Json cells = Json::array(), columns = Json::array();
  std::vector<double> logs, x;
  std::string unit = "s";
  for (const auto& c : d.columns) {
    if (!c.gap) continue;
    columns.push_back(c.name);
    unit = tau_unit(c);
    const double scale = tau_scale(c);
    int level = c.gap->first_level - 1;
    for (const auto& l : c.gap->levels) {
      ++level;
      const double lr = l.ratio > 0.0 ? std::log2(l.ratio) : std::nan("");
      const double t = l.tau * scale;
      cells.push_back({{"column", c.name},
                       {"level", level},
                       {"tau", t},
                       {"x0", t / std::sqrt(2.0)},
                       {"x1", t * std::sqrt(2.0)},
                       {"log2ratio", number(lr)},
                       {"ratio", number(l.ratio)},
                       {"z", number(l.z)},
                       {"outside", l.outside}});
      logs.push_back(lr);
      x.insert(x.end(), {t / std::sqrt(2.0), t * std::sqrt(2.0)});
    }
  }
  const auto xr = padded_log_range(x);
  const double m = max_abs(logs, 1.0);
  const int rows = std::max<int>(1, static_cast<int>(columns.size()));
  Json spec = {{"$schema", "https://vega.github.io/schema/vega/v5.json"},
               {"width", kPlotWidth},
               {"height", 30 * rows},
               {"padding", 5},
               {"title",
                {{"text", "gap: data WV / baseline WV per scale and axis (log2; outlined: outside the reference band)"},
                 {"anchor", "start"},
                 {"fontSize", 13}}}};
  spec["data"] = {{{"name", "cells"}, {"values", std::move(cells)}}};
  spec["scales"] = {
      {{"name", "x"},
       {"type", "log"},
       {"domain", {std::pow(10.0, xr[0]), std::pow(10.0, xr[1])}},
       {"range", "width"},
       {"zero", false}},
      {{"name", "y"}, {"type", "band"}, {"domain", std::move(columns)}, {"range", "height"}, {"padding", 0.08}},
      {{"name", "color"},
       {"type", "linear"},
       {"domain", {-m, 0.0, m}},
       {"range", {"#2166ac", "#f7f7f7", "#b2182b"}},
       {"clamp", true}}};
  spec["axes"] = {{{"orient", "bottom"}, {"scale", "x"}, {"title", "tau [" + unit + "]"}},
                  {{"orient", "left"}, {"scale", "y"}, {"title", "axis"}}};
  spec["legends"] = {{{"fill", "color"}, {"type", "gradient"}, {"title", "log2 ratio"}, {"orient", "right"}}};
  Json enc = {
      {"x", {{"scale", "x"}, {"field", "x0"}}},
      {"x2", {{"scale", "x"}, {"field", "x1"}}},
      {"y", {{"scale", "y"}, {"field", "column"}}},
      {"height", {{"scale", "y"}, {"band", 1}}},
      {"fill", {{"signal", "isValid(datum.log2ratio) ? scale('color', datum.log2ratio) : '#dddddd'"}}},
      {"stroke", {{"signal", "datum.outside ? '#000000' : '#ffffff'"}}},
      {"strokeWidth", {{"signal", "datum.outside ? 1.5 : 0.5"}}},
      {"tooltip",
       {{"signal",
         "{'axis': datum.column, 'level': datum.level, 'tau [" + unit +
             "]': format(datum.tau, '.4~g'), 'ratio': format(datum.ratio, '.4~g'), 'z': format(datum.z, '.3~g'), "
             "'outside the band': datum.outside ? 'yes' : 'no'}"}}}};
  spec["marks"] = {{{"type", "rect"}, {"from", {{"data", "cells"}}}, {"encode", {{"update", enc}}}}};
  return spec;
}

Json gap_windows_spec(const ReportColumn& c) {
  const gap::GapResult& g = *c.gap;
  const double scale = tau_scale(c);
  Json cells = Json::array();
  std::vector<double> z;
  for (const auto& w : g.windows) {
    cells.push_back({{"t0", static_cast<double>(w.first_sample) * scale},
                     {"t1", static_cast<double>(w.last_sample + 1) * scale},
                     {"tau", w.tau * scale},
                     {"y0", w.tau * scale / std::sqrt(2.0)},
                     {"y1", w.tau * scale * std::sqrt(2.0)},
                     {"ratio", number(w.ratio)},
                     {"z", number(w.z)}});
    z.push_back(w.z);
  }
  double tau_lo = 1.0, tau_hi = 2.0;
  if (!g.levels.empty()) {
    tau_lo = g.levels.front().tau * scale / std::sqrt(2.0);
    tau_hi = g.levels.back().tau * scale * std::sqrt(2.0);
  }
  const double m = max_abs(z, 3.0);
  const double duration = static_cast<double>(std::max<std::int64_t>(c.n, 1)) * scale;
  const std::string unit = tau_unit(c);
  Json spec = {
      {"$schema", "https://vega.github.io/schema/vega/v5.json"},
      {"width", kPlotWidth},
      {"height", 220},
      {"padding", 5},
      {"title",
       {{"text", c.name + ": window x scale map (windows of " + num(static_cast<double>(g.window_length) * scale, 4) +
                     " " + unit + "; only cells beyond the threshold)"},
        {"anchor", "start"},
        {"fontSize", 13}}}};
  spec["data"] = {{{"name", "cells"}, {"values", std::move(cells)}}};
  spec["scales"] = {
      {{"name", "x"}, {"type", "linear"}, {"domain", {0.0, duration}}, {"range", "width"}, {"zero", false}},
      {{"name", "y"}, {"type", "log"}, {"domain", {tau_lo, tau_hi}}, {"range", "height"}, {"zero", false}},
      {{"name", "color"},
       {"type", "linear"},
       {"domain", {-m, 0.0, m}},
       {"range", {"#2166ac", "#f7f7f7", "#b2182b"}},
       {"clamp", true}}};
  spec["axes"] = {{{"orient", "bottom"}, {"scale", "x"}, {"title", "time [" + unit + "]"}},
                  {{"orient", "left"}, {"scale", "y"}, {"title", "tau [" + unit + "]"}}};
  spec["legends"] = {{{"fill", "color"}, {"type", "gradient"}, {"title", "z"}, {"orient", "right"}}};
  Json enc = {
      {"x", {{"scale", "x"}, {"field", "t0"}}},
      {"x2", {{"scale", "x"}, {"field", "t1"}}},
      {"y", {{"scale", "y"}, {"field", "y0"}}},
      {"y2", {{"scale", "y"}, {"field", "y1"}}},
      {"fill", {{"scale", "color"}, {"field", "z"}}},
      {"stroke", {{"value", "#333333"}}},
      {"strokeWidth", {{"value", 0.5}}},
      {"tooltip",
       {{"signal",
         "{'time [" + unit + "]': format(datum.t0, '.4~g') + ' to ' + format(datum.t1, '.4~g'), 'tau [" + unit +
             "]': format(datum.tau, '.4~g'), 'ratio': format(datum.ratio, '.3~g'), 'z': format(datum.z, '.3~g')}"}}}};
  Json marks = Json::array();
  marks.push_back({{"type", "rect"}, {"from", {{"data", "cells"}}}, {"encode", {{"update", enc}}}});
  if (g.windows.empty())
    marks.push_back(
        {{"type", "text"},
         {"encode",
          {{"enter",
            {{"x", {{"signal", "width / 2"}}},
             {"y", {{"signal", "height / 2"}}},
             {"align", {{"value", "center"}}},
             {"fill", {{"value", "#555555"}}},
             {"text", {{"value", "no (window, scale) cell departs from the record's typical window"}}}}}}}});
  spec["marks"] = std::move(marks);
  return spec;
}

}  // namespace gmwm::report::detail
