// Vega inlined into the report, and the page's own script and style.
//
// Debian 12's libjs-vega (5.22) installs Vega as separate UMD modules under
// /usr/share/javascript/vega (no single vega.min.js). Their browser-globals branch is
// unusable as shipped (every module assigns the global `vega` afresh), so each module is
// wrapped in a function that gives it CommonJS `exports`/`module`/`require`: the UMD
// header then takes its CommonJS branch, and `require` returns the modules loaded before
// it (they come in dependency order). The shim afterwards composes `vega` as Vega's own
// index.js does: the utility, scenegraph and loader exports, View and parse, and the
// transforms of vega-transforms, vega-view-transforms and vega-encode registered with
// the dataflow (geo, force, hierarchy, label, regression, voronoi, wordcloud and
// crossfilter are left out: the report's specs use none of them).

#include <cctype>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "gmwm/engine/error.h"
#include "html_report_detail.h"

#ifndef GMWM_VEGA_DIR
#define GMWM_VEGA_DIR ""
#endif

namespace gmwm::report::detail {

namespace {

// In dependency order. vega-functions requires "vega-selections", which Debian installs
// as vega-selection.min.js (the loader maps the name).
constexpr const char* kModules[] = {"vega-util",       "vega-canvas",          "vega-time",       "vega-format",
                                    "vega-loader",     "vega-dataflow",        "vega-scale",      "vega-scenegraph",
                                    "vega-expression", "vega-selection",       "vega-statistics", "vega-event-selector",
                                    "vega-functions",  "vega-runtime",         "vega-parser",     "vega-view",
                                    "vega-transforms", "vega-view-transforms", "vega-encode"};

bool read_file(const std::string& path, std::string* out) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::ostringstream ss;
  ss << in.rdbuf();
  *out = ss.str();
  return static_cast<bool>(in) || in.eof();
}

// Safe inside <script>: no "</script" (written "<\/script", the same inside a JS string
// or regex) and no source-map comment (it would make a browser look for a file).
std::string script_safe(std::string js) {
  std::string out;
  out.reserve(js.size());
  std::istringstream lines(js);
  std::string line;
  while (std::getline(lines, line)) {
    if (line.rfind("//# sourceMappingURL=", 0) == 0) continue;
    out += line;
    out += '\n';
  }
  auto lower = [](std::string t) {
    for (char& ch : t) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    return t;
  };
  for (std::size_t p = lower(out).find("</script"); p != std::string::npos; p = lower(out).find("</script", p + 2))
    out.insert(p + 1, "\\");
  for (std::size_t p = out.find("<!--"); p != std::string::npos; p = out.find("<!--", p + 4)) out.insert(p + 1, "\\");
  return out;
}

std::string read_module(const std::string& dir, const std::string& name) {
  std::string text;
  const std::string path = dir + "/" + name + ".min.js";
  if (!read_file(path, &text))
    throw InputError("HTML report: cannot read Vega module '" + path +
                     "', expected Debian's libjs-vega (apt-get install libjs-vega; or set GMWM_VEGA_DIR)");
  return text;
}

}  // namespace

std::string vega_dir() {
  if (const char* env = std::getenv("GMWM_VEGA_DIR"); env && *env) return env;
  return GMWM_VEGA_DIR;
}

std::string vega_script() {
  const std::string dir = vega_dir();
  if (dir.empty())
    throw InputError(
        "HTML report: gmwm was configured without Vega; install Debian's libjs-vega and re-run cmake "
        "(or set GMWM_VEGA_DIR to the folder with vega-view.min.js)");
  std::string s =
      "var __gmwmModules = {};\n"
      "function __gmwmRequire(name) {\n"
      "  if (name === 'vega-selections') name = 'vega-selection';\n"
      "  var m = __gmwmModules[name];\n"
      "  if (!m) throw new Error('Vega module ' + name + ' is not inlined');\n"
      "  return m;\n"
      "}\n";
  for (const char* name : kModules) {
    s += "/* " + std::string(name) + " (Debian libjs-vega) */\n(function (exports, module, require) {\n";
    s += script_safe(read_module(dir, name));
    s += "})(__gmwmModules['" + std::string(name) + "'] = {}, {}, __gmwmRequire);\n";
  }
  s += R"JS(var vega = (function (m) {
  var df = m['vega-dataflow'];
  m['vega-util'].extend(df.transforms, m['vega-transforms'], m['vega-view-transforms'], m['vega-encode']);
  return Object.assign({}, m['vega-util'], m['vega-loader'], m['vega-scenegraph'], {
    View: m['vega-view'].View, parse: m['vega-parser'].parse, expressionFunction: m['vega-functions'].expressionFunction,
    scale: m['vega-scale'].scale, scheme: m['vega-scale'].scheme, transforms: df.transforms
  });
})(__gmwmModules);
)JS";
  return s;
}

std::string page_script() {
  return R"JS((function () {
  'use strict';
  var errors = document.getElementById('gmwm-errors');
  var warnings = document.getElementById('gmwm-warnings');
  function note(box, msg) {
    var line = document.createElement('div');
    line.textContent = String(msg);
    box.appendChild(line);
    box.hidden = false;
  }
  function text(args) { return Array.prototype.map.call(args, String).join(' '); }
  function logger(id) {
    var level = 2;
    return {
      level: function (l) { if (arguments.length) { level = +l; return this; } return level; },
      error: function () { if (level >= 1) note(errors, id + ': ' + text(arguments)); return this; },
      warn: function () { if (level >= 2) note(warnings, id + ': ' + text(arguments)); return this; },
      info: function () { return this; },
      debug: function () { return this; }
    };
  }
  function exportLinks(el, view, id) {
    var bar = el.querySelector('.export');
    if (!bar) return;
    ['svg', 'png'].forEach(function (fmt) {
      var a = document.createElement('a');
      a.href = '#';
      a.textContent = fmt.toUpperCase();
      a.title = 'save this plot as ' + fmt.toUpperCase() + ' (rendered by Vega)';
      a.addEventListener('click', function (ev) {
        ev.preventDefault();
        view.toImageURL(fmt, fmt === 'png' ? 2 : 1).then(function (url) {
          var link = document.createElement('a');
          link.href = url;
          link.download = id + '.' + fmt;
          document.body.appendChild(link);
          link.click();
          link.remove();
        }).catch(function (e) { note(errors, id + ': export failed: ' + e); });
      });
      bar.appendChild(a);
    });
  }
  var body = document.body;
  var specs = [];
  try {
    specs = JSON.parse(document.getElementById('gmwm-specs').textContent);
  } catch (e) {
    note(errors, 'cannot read the plot specifications: ' + e);
  }
  if (typeof vega === 'undefined' || !vega.View) {
    note(errors, 'Vega did not load: no plot can be drawn');
    specs = [];
  }
  var pending = specs.length, rendered = 0;
  window.gmwmViews = {};  // the Vega views by plot id, for scripting and debugging
  function finished() {
    body.setAttribute('data-gmwm-rendered', String(rendered));
    body.setAttribute('data-gmwm-status', 'done');
  }
  function one() { if (--pending === 0) finished(); }
  if (pending === 0) finished();
  specs.forEach(function (entry) {
    var el = document.getElementById(entry.id);
    if (!el) { note(errors, entry.id + ': no plot container'); one(); return; }
    try {
      var view = new vega.View(vega.parse(entry.spec), {
        renderer: 'svg', container: el.querySelector('.view'), hover: true, logger: logger(entry.id)
      });
      window.gmwmViews[entry.id] = view;
      view.runAsync().then(function () {
        if (el.querySelector('.view svg')) {
          el.setAttribute('data-rendered', 'svg');
          rendered++;
          exportLinks(el, view, entry.id);
        } else {
          note(errors, entry.id + ': Vega produced no SVG');
        }
        one();
      }).catch(function (e) { note(errors, entry.id + ': ' + e); one(); });
    } catch (e) {
      note(errors, entry.id + ': ' + e);
      one();
    }
  });
})();
)JS";
}

std::string page_style() {
  return R"CSS(body { font: 14px/1.45 system-ui, -apple-system, "Segoe UI", Helvetica, Arial, sans-serif; margin: 0;
  color: #1d1d1f; background: #fafafa; }
header { background: #24292f; color: #fff; padding: 14px 28px; }
header h1 { margin: 0 0 4px 0; font-size: 20px; }
header p { margin: 2px 0; color: #d0d7de; }
header code { color: #fff; }
main { padding: 8px 28px 40px 28px; max-width: 1500px; }
nav a { margin-right: 12px; }
section.column { background: #fff; border: 1px solid #d0d7de; border-radius: 6px; padding: 12px 18px; margin: 18px 0; }
section.column h2 { margin: 4px 0 6px 0; font-size: 18px; }
h3 { font-size: 15px; margin: 14px 0 6px 0; }
h4 { font-size: 14px; margin: 12px 0 4px 0; }
.facts { color: #57606a; margin: 4px 0; }
.facts li.warn { color: #9a6700; }
.quality { color: #8a1c1c; background: #fff4f4; border-left: 3px solid #d62728; padding: 4px 8px; margin: 6px 0; }
.gmwm-plot { margin: 10px 0; }
.gmwm-plot .hint { color: #57606a; font-size: 12px; }
.gmwm-plot .export a { margin-left: 8px; font-size: 12px; }
.vega-bindings { font-size: 12px; color: #57606a; }
.vega-bind { display: inline-block; margin-right: 14px; }
table { border-collapse: collapse; margin: 6px 0 10px 0; font-size: 13px; }
caption { text-align: left; color: #57606a; padding: 2px 0; }
th, td { border: 1px solid #d0d7de; padding: 3px 8px; vertical-align: top; }
th { background: #f6f8fa; text-align: left; }
td.num { text-align: right; font-variant-numeric: tabular-nums; font-family: ui-monospace, Menlo, Consolas, monospace; }
td.note { color: #57606a; font-size: 12px; max-width: 520px; }
tr.chosen td { background: #fff4c2; font-weight: 600; }
tr.outside td { background: #ffebe9; }
.badge { background: #bf8700; color: #fff; border-radius: 8px; padding: 0 7px; font-size: 11px; font-weight: 600; }
p.model, code { font-family: ui-monospace, Menlo, Consolas, monospace; font-size: 12px; }
.errors { background: #ffebe9; border: 1px solid #cf222e; color: #82071e; padding: 8px 12px; margin: 10px 0;
  white-space: pre-wrap; }
.warnings { background: #fff8c5; border: 1px solid #bf8700; padding: 8px 12px; margin: 10px 0; white-space: pre-wrap; }
footer { color: #57606a; font-size: 12px; padding: 0 28px 24px 28px; }
)CSS";
}

}  // namespace gmwm::report::detail
