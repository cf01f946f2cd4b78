// Names from files (column names, the source line) reach every export format as text only:
// each format's output, read back with a real parser (yaml-cpp, nlohmann::json, tinyxml2),
// has exactly the structure of the same export with plain names, whatever the names hold
// (issue 25: a column named "--><plugin filename=.../><!--" added a <plugin> element that
// Gazebo would load).
#include <functional>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <tinyxml2.h>
#include <yaml-cpp/yaml.h>

#include "gmwm/engine/model_syntax.h"
#include "gmwm/io/export.h"
#include "gmwm/io/units.h"

namespace gmwm::io {
namespace {

// Each ends in its axis letter and holds its sensor's name, as an export needs.
const std::vector<std::string> kHostileGyro = {
    "gyro--><plugin filename=\"/x/libevil.so\"/><!--x",
    "gyro\n  injected_key: 1\n# y",
    "gyro</sensor><sensor name='evil'>\x1b[2J\x1b]0;title\x07-z",
};
const std::vector<std::string> kHostileAccel = {
    "accel\": 1, \"evil\": {\"a\": \"x",
    "accel]]>&amp;<![CDATA[ \xC2\x9B"
    "31m}{: [y",
    "accel\r\n%YAML:1.0\n---\nevil: z",
};

ExportColumn column(const std::string& name, SensorKind kind, const std::string& spec) {
  ExportColumn c;
  c.name = name;
  c.kind = kind;
  c.freq = 200.0;
  c.n = 65536;
  c.unit = si_unit(kind);
  c.model = parse_model(spec, ProcessContext{c.freq, true});
  c.theta = c.model.given_values();
  c.model = c.model.canonical(&c.theta);
  return c;
}

std::vector<ExportColumn> columns(const std::vector<std::string>& gyro, const std::vector<std::string>& accel) {
  std::vector<ExportColumn> v;
  for (const auto& n : gyro)
    v.push_back(column(n, SensorKind::kGyro, "WN(sigma2=5.8e-06)+RW(gamma2=1.9e-12)+AR1(phi=0.9999,sigma2=1e-9)"));
  for (const auto& n : accel)
    v.push_back(column(n, SensorKind::kAccel, "WN(sigma2=8e-04)+RW(gamma2=4.5e-08)+SIN(A2=1e-6,f=0.05)"));
  return v;
}

// The structure a consumer reads: every key path with its scalar value (YAML, JSON), or every
// element path with its attributes and text (XML). Comments are not structure.
std::multiset<std::string> yaml_structure(std::string text) {
  if (text.rfind("%YAML:", 0) == 0) text.erase(0, text.find('\n') + 1);  // OpenCV's directive line
  std::multiset<std::string> out;
  const std::function<void(const YAML::Node&, const std::string&)> walk = [&](const YAML::Node& n,
                                                                              const std::string& at) {
    if (n.IsMap()) {
      for (const auto& kv : n) walk(kv.second, at + "/" + kv.first.as<std::string>());
    } else if (n.IsSequence()) {
      for (std::size_t i = 0; i < n.size(); ++i) walk(n[i], at + "[" + std::to_string(i) + "]");
    } else {
      out.insert(at + "=" + (n.IsScalar() ? n.Scalar() : std::string("~")));
    }
  };
  walk(YAML::Load(text), "");
  return out;
}

std::multiset<std::string> json_structure(const std::string& text) {
  std::multiset<std::string> out;
  const std::function<void(const nlohmann::json&, const std::string&)> walk = [&](const nlohmann::json& j,
                                                                                  const std::string& at) {
    if (j.is_object()) {
      for (const auto& [k, v] : j.items()) walk(v, at + "/" + k);
    } else if (j.is_array()) {
      for (std::size_t i = 0; i < j.size(); ++i) walk(j[i], at + "[" + std::to_string(i) + "]");
    } else {
      out.insert(at + "=" + j.dump());
    }
  };
  walk(nlohmann::json::parse(text), "");
  return out;
}

std::multiset<std::string> xml_structure(const std::string& text, std::vector<std::string>* comments) {
  tinyxml2::XMLDocument doc;
  EXPECT_EQ(doc.Parse(text.c_str(), text.size()), tinyxml2::XML_SUCCESS) << doc.ErrorStr() << "\n" << text;
  std::multiset<std::string> out;
  const std::function<void(const tinyxml2::XMLNode*, const std::string&)> walk = [&](const tinyxml2::XMLNode* n,
                                                                                     const std::string& at) {
    for (; n; n = n->NextSibling()) {
      if (const auto* c = n->ToComment()) {
        comments->push_back(c->Value());
      } else if (const auto* e = n->ToElement()) {
        std::string path = at + "/" + e->Name();
        for (const auto* a = e->FirstAttribute(); a; a = a->Next())
          path += std::string("[@") + a->Name() + "=" + a->Value() + "]";
        out.insert(path + (e->GetText() ? std::string("=") + e->GetText() : std::string()));
        walk(e->FirstChild(), path);
      } else if (const auto* t = n->ToText()) {
        if (!t->CData()) continue;
        out.insert(at + "#cdata");
      }
    }
  };
  walk(doc.FirstChild(), "");
  return out;
}

struct FormatCase {
  ExportFormat format;
  Aggregation aggregation;
};

class ExportHostileNames : public ::testing::TestWithParam<FormatCase> {};

TEST_P(ExportHostileNames, ReadBackWithARealParserHaveTheStructureOfThePlainNamedExport) {
  const FormatCase fc = GetParam();
  ExportOptions o;
  o.format = fc.format;
  o.aggregation = fc.aggregation;
  const ExportResult plain = render_export(columns({"gyro_x", "gyro_y", "gyro_z"}, {"accel_x", "accel_y", "accel_z"}),
                                           o, "gmwm fit result fit.json (data imu.csv)");
  const ExportResult hostile = render_export(columns(kHostileGyro, kHostileAccel), o,
                                             "gmwm fit result --><x/>\n: evil\x1b[31m.json (data </script>.csv)");
  switch (fc.format) {
    case ExportFormat::kKalibr:
    case ExportFormat::kOpenVins:
    case ExportFormat::kVins:
    case ExportFormat::kOrbSlam3:
      EXPECT_EQ(yaml_structure(hostile.content), yaml_structure(plain.content)) << hostile.content;
      break;
    case ExportFormat::kBasalt:
      EXPECT_EQ(json_structure(hostile.content), json_structure(plain.content)) << hostile.content;
      break;
    case ExportFormat::kGzSdf:
    case ExportFormat::kRotors: {
      std::vector<std::string> plain_comments, hostile_comments;
      EXPECT_EQ(xml_structure(hostile.content, &hostile_comments), xml_structure(plain.content, &plain_comments))
          << hostile.content;
      EXPECT_EQ(hostile_comments.size(), plain_comments.size()) << hostile.content;
      // The names are still there for the reader, as comment text.
      if (fc.aggregation == Aggregation::kPerAxis) {
        bool named = false;
        for (const auto& c : hostile_comments) named = named || c.find("plugin filename") != std::string::npos;
        EXPECT_TRUE(named) << hostile.content;
      }
      break;
    }
  }
  // No control byte but line breaks reaches any text of the export (ESC, CSI, CR).
  for (const std::string* text : {&hostile.content, hostile.sidecar ? &*hostile.sidecar : nullptr}) {
    if (!text) continue;
    for (unsigned char ch : *text)
      EXPECT_TRUE(ch >= 0x20 || ch == '\n') << "control byte " << int(ch) << " in\n" << *text;
    EXPECT_EQ(text->find("\xC2\x9B"), std::string::npos) << "CSI in\n" << *text;
  }
}

std::vector<FormatCase> every_format() {
  std::vector<FormatCase> v;
  for (ExportFormat f : {ExportFormat::kKalibr, ExportFormat::kOpenVins, ExportFormat::kVins, ExportFormat::kOrbSlam3,
                         ExportFormat::kBasalt, ExportFormat::kGzSdf, ExportFormat::kRotors}) {
    v.push_back({f, Aggregation::kMean});
    if (has_per_axis_fields(f)) v.push_back({f, Aggregation::kPerAxis});
  }
  return v;
}

INSTANTIATE_TEST_SUITE_P(EveryFormat, ExportHostileNames, ::testing::ValuesIn(every_format()), [](const auto& info) {
  std::string name = to_string(info.param.format);
  name += info.param.aggregation == Aggregation::kPerAxis ? "_per_axis" : "_mean";
  for (char& c : name)
    if (c == '-') c = '_';
  return name;
});

TEST(ExportHostileNames, CoverEveryFormat) {
  for (const char* name : {"kalibr", "openvins", "vins", "orbslam3", "basalt", "gz-sdf", "rotors"})
    EXPECT_TRUE(parse_export_format(name)) << name;
  EXPECT_EQ(export_format_names(), "kalibr, openvins, vins, orbslam3, basalt, gz-sdf, rotors")
      << "a new format: add it to every_format()";
}

}  // namespace
}  // namespace gmwm::io
