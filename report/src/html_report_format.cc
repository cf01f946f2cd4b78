// Escaping, numbers and the series the report's plots draw (html_report_detail.h).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <span>

#include <sstream>

#include "html_report_detail.h"
#include "gmwm/engine/number_text.h"

namespace gmwm::report::detail {

std::string html_escape(std::string_view s) {
  std::string out;
  out.reserve(s.size() + 16);
  for (const char ch : s) {
    switch (ch) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        // Control bytes (from a name in a file) as the replacement character: a page
        // carries no escape sequence to whoever prints it.
        if ((static_cast<unsigned char>(ch) < 0x20 && ch != '\t' && ch != '\n' && ch != '\r') || ch == 0x7F)
          out += "\xEF\xBF\xBD";
        else
          out += ch;
    }
  }
  return out;
}

std::string script_json(const Json& j) {
  // Invalid UTF-8 in a user string (a column name) is replaced rather than thrown on.
  const std::string text = j.dump(-1, ' ', false, Json::error_handler_t::replace);
  std::string out;
  out.reserve(text.size() + 64);
  for (const char ch : text) {
    switch (ch) {
      case '<':
        out += "\\u003c";
        break;
      case '>':
        out += "\\u003e";
        break;
      case '&':
        out += "\\u0026";
        break;
      default:
        out += ch;
    }
  }
  return out;
}

std::string num(double x, int digits) { return significant(x, digits, NonFinite::kDash); }

double tau_scale(const ReportColumn& c) { return c.freq_known && c.freq > 0.0 ? 1.0 / c.freq : 1.0; }

std::string tau_unit(const ReportColumn& c) { return c.freq_known && c.freq > 0.0 ? "s" : "samples"; }

std::string data_unit(const ReportColumn& c) { return c.unit.empty() ? "U" : c.unit; }

std::string wv_label(const WaveletVariance& wv) {
  if (wv.estimator == "classical" || wv.estimator.empty()) return "classical WV";
  std::string s = wv.estimator + " WV";
  if (wv.efficiency) s += " (eff. " + num(*wv.efficiency, 3) + ")";
  return s;
}

WvSeries wv_series(const WaveletVariance& wv, const ReportColumn& c) {
  WvSeries s;
  s.name = wv_label(wv);
  const double scale = tau_scale(c);
  const double nan = std::nan("");
  auto positive = [&](const std::vector<double>& v, std::size_t j) {
    return j < v.size() && std::isfinite(v[j]) && v[j] > 0.0 ? v[j] : nan;
  };
  for (std::size_t j = 0; j < wv.wv.size() && j < wv.tau.size(); ++j) {
    if (!(std::isfinite(wv.wv[j]) && wv.wv[j] > 0.0)) continue;
    s.points.push_back(
        {static_cast<int>(j) + 1, wv.tau[j] * scale, wv.wv[j], positive(wv.ci_low, j), positive(wv.ci_high, j)});
  }
  return s;
}

bool has_theta(const FitResult& f) {
  return f.status != FitStatus::kFailed && f.model.num_parameters() > 0 && f.theta.size() == f.model.num_parameters() &&
         f.theta.allFinite();
}

const std::vector<double>& model_tau(const ReportColumn& c) {
  const WaveletVariance* longest = &c.wvs.front();
  for (const auto& w : c.wvs)
    if (w.levels() > longest->levels()) longest = &w;
  return longest->tau;
}

const FitResult* shown_model(const ReportColumn& c) {
  if (c.fit && has_theta(*c.fit)) return &*c.fit;
  if (c.selection) {
    if (has_theta(c.selection->best_fit)) return &c.selection->best_fit;
    if (!c.selection->ranking.empty() && has_theta(c.selection->ranking.front().fit))
      return &c.selection->ranking.front().fit;
  }
  return nullptr;
}

// Components below this share of the model's WV at every scale are not drawn.
constexpr double kNegligibleShare = 1e-6;

std::vector<Curve> model_curves(const Model& model, const Eigen::VectorXd& theta,
                                const std::vector<double>& tau_samples, double scale, const std::string& label,
                                bool components) {
  std::vector<Curve> out;
  if (tau_samples.empty() || theta.size() != model.num_parameters() || !theta.allFinite()) return out;
  auto keep = [&](Curve c, const double* v) {
    for (std::size_t j = 0; j < tau_samples.size(); ++j)
      if (std::isfinite(v[j]) && v[j] > 0.0) {
        c.tau.push_back(tau_samples[j] * scale);
        c.value.push_back(v[j]);
      }
    if (!c.tau.empty()) out.push_back(std::move(c));
  };
  const Eigen::VectorXd total = model.wv(theta, tau_samples);
  keep({label, false, {}, {}}, total.data());
  if (!components || model.num_components() < 2) return out;
  std::vector<double> v(tau_samples.size());
  for (int k = 0; k < model.num_components(); ++k) {
    const Process& p = *model.components()[static_cast<std::size_t>(k)].process;
    const std::span<const double> th(theta.data() + model.offset(k), static_cast<std::size_t>(p.size()));
    p.wv(th, tau_samples, v);
    // A collapsed component (its share of the model below kNegligibleShare at every scale)
    // would only stretch the axis by ten decades: its table row says where it went.
    bool visible = false;
    for (std::size_t j = 0; j < v.size(); ++j)
      visible = visible || v[j] > kNegligibleShare * total(static_cast<Eigen::Index>(j));
    if (!visible) continue;
    keep({std::to_string(k + 1) + ": " + p.name(), true, {}, {}}, v.data());
  }
  return out;
}

namespace {

// The page's series colours (Tableau 10, the plots' palette): a name's colour is the first of
// these no other name of the page has taken, so that one series keeps its colour across plots.
constexpr std::array<const char*, 10> kSeriesPalette = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd",
                                                        "#8c564b", "#e377c2", "#17becf", "#bcbd22", "#7f7f7f"};

bool in_palette(const Json& colour) {
  return colour.is_string() &&
         std::find(kSeriesPalette.begin(), kSeriesPalette.end(), colour.get<std::string>()) != kSeriesPalette.end();
}

// A plot's narrowest width: below it, a plot's axes and legend crowd its curves.
constexpr int kMinPlotWidth = 360;

// The spec as wide as its container (Vega-Lite's width "container"): the width a signal of the
// container's width, resized with the window, the legend and axes inside it.
void fill_width(Json& spec) {
  if (!spec.contains("width") || !spec["width"].is_number()) return;
  const int fixed = spec["width"].get<int>();
  spec.erase("width");
  spec["autosize"] = {{"type", "fit-x"}, {"contains", "padding"}, {"resize", true}};
  const std::string w = "isFinite(containerSize()[0]) && containerSize()[0] > " + std::to_string(kMinPlotWidth) +
                        " ? containerSize()[0] : " + std::to_string(std::max(fixed, kMinPlotWidth));
  if (!spec.contains("signals")) spec["signals"] = Json::array();
  spec["signals"].insert(spec["signals"].begin(),
                         Json{{"name", "width"}, {"init", w}, {"on", {{{"events", "window:resize"}, {"update", w}}}}});
}

}  // namespace

std::string Plots::add(const std::string& id, const std::string& kind, Json spec) {
  fill_width(spec);
  if (spec.contains("scales"))
    for (Json& scale : spec["scales"]) {
      if (scale.value("name", "") != "color" || scale.value("type", "") != "ordinal") continue;
      Json& domain = scale["domain"];
      Json& range = scale["range"];
      if (!domain.is_array() || !range.is_array()) continue;
      for (std::size_t i = 0; i < domain.size() && i < range.size(); ++i) {
        if (!domain[i].is_string() || !in_palette(range[i])) continue;  // a fixed colour (the truth, a reference) stays
        // The fitted model is one series whatever its plot calls it ("model", "model AR1+WN").
        std::string name = domain[i].get<std::string>();
        if (name.rfind("model", 0) == 0) name = "model";
        auto it = series_colours.find(name);
        if (it == series_colours.end()) {
          const char* free = kSeriesPalette[series_colours.size() % kSeriesPalette.size()];
          for (const char* c : kSeriesPalette) {
            bool taken = false;
            for (const auto& [n, col] : series_colours) taken = taken || col == c;
            if (!taken) {
              free = c;
              break;
            }
          }
          it = series_colours.emplace(name, free).first;
        }
        range[i] = it->second;
      }
    }
  specs.push_back({{"id", id}, {"kind", kind}, {"spec", std::move(spec)}});
  // The log-log plots (wv, gap-curves) zoom and pan; the maps show values on hover, the
  // navigation curves at each output time, the stability deviations at each point.
  const bool zooms = kind == "wv" || kind == "gap-curves";
  const bool curves = kind.rfind("nav-", 0) == 0;
  const bool points = kind.rfind("stability", 0) == 0, hat = kind == "stability-hat";
  return "<div class=\"gmwm-plot\" data-plot=\"" + kind + "\" id=\"" + id +
         "\"><div class=\"view\"></div><div class=\"hint\">" +
         (zooms    ? "drag to pan, wheel to zoom, double-click to reset; hover a point for its values"
          : curves ? "hover a curve for its value at each output time"
          : hat    ? "hover a point for its value, interval and degrees of freedom"
          : points ? "hover a point for its value, interval, degrees of freedom and noise"
                   : "hover a cell for its values") +
         "<span class=\"export\"></span></div></div>\n";
}

// Catches errors of every later script, Vega's modules included.
const char* const kErrorCapture = R"JS(<script>
(function () {
  function note(msg) {
    var box = document.getElementById('gmwm-errors');
    var line = document.createElement('div');
    line.textContent = String(msg);
    box.appendChild(line);
    box.hidden = false;
  }
  window.onerror = function (msg, src, line, col) {
    note('script error: ' + msg + (line ? ' (line ' + line + ':' + col + ')' : ''));
  };
  window.addEventListener('unhandledrejection', function (e) {
    note('unhandled promise rejection: ' + ((e.reason && e.reason.message) || e.reason));
  });
})();
</script>
)JS";

std::string html_page(const std::string& title, const std::string& body, const Plots& plots, const std::string& vega) {
  std::ostringstream page;
  page << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
       << "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<meta name=\"generator\" "
          "content=\"gmwm "
       << html_escape(version()) << "\">\n<title>" << html_escape(title) << "</title>\n<style>\n"
       << page_style() << "</style>\n</head>\n<body>\n"
       << body << "<script type=\"application/json\" id=\"gmwm-specs\">" << script_json(plots.specs)
       << "</script>\n<script>\n"
       << vega << "</script>\n<script>\n"
       << page_script() << "</script>\n</body>\n</html>\n";
  return page.str();
}

}  // namespace gmwm::report::detail
