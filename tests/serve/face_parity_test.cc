// The command line and the web app refuse the same bad values with the same words and accept
// the same good ones with the same document (issue 45), over the one table the Python face
// is held to as well (tests/data/face_parity.json; python/tests/test_face_parity.py).

#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "serve_fixture.h"

namespace gmwm::test {
namespace {

OJson parity_table() {
  std::ifstream in(std::string(GMWM_SOURCE_DIR) + "/tests/data/face_parity.json");
  EXPECT_TRUE(in.good()) << "tests/data/face_parity.json";
  return OJson::parse(in);
}

bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

// The model every case without its own is run with.
constexpr const char* kParityModel = "WN+RW";

TEST_F(ServeAppTest, TheCliAndTheWebAppRefuseEveryBadValueOfTheTableWithTheSameWords) {
  const std::string d = open_imu();
  const OJson table = parity_table();
  ASSERT_GE(table.at("refusals").size(), 5u);
  for (const OJson& c : table.at("refusals")) {
    const std::string study = c.at("study"), option = c.at("option"), field = c.at("field"), words = c.at("words");
    const bool own_model = option == "--model" || option == "--models" || study == "stability";  // none
    std::vector<std::string> args = {study, "recordings/imu.csv", "--columns", "gyro_x", option};
    if (!c.at("value").is_null()) args.push_back(c.at("value"));  // null: a switch
    if (!own_model) args.insert(args.end(), {"--model", kParityModel});
    const OJson also = c.value("also", OJson::object());  // switches the case needs besides
    for (const auto& [flag, on] : also.items()) args.push_back(flag);
    const CliRun cli = run_gmwm(args, dir_);
    EXPECT_EQ(cli.exit_code, 2) << option << ": " << cli.err;
    const std::string line = cli.err.substr(0, cli.err.find_last_not_of('\n') + 1);
    EXPECT_EQ(line.find('\n'), std::string::npos) << "one line: " << cli.err;
    EXPECT_TRUE(ends_with(line, words)) << option << "\n cli: " << line << "\n words: " << words;

    OJson body = {{"dataset", d}, {"column", "gyro_x"}, {field, c.at("json")}};
    if (!own_model) body["model"] = kParityModel;
    for (const auto& [flag, on] : also.items()) body[flag.substr(2)] = on;
    const serve::HttpResponse r = post("/api/" + study, body);
    EXPECT_EQ(r.status, 400) << r.body;
    const std::string web = OJson::parse(r.body).value("error", std::string());
    EXPECT_TRUE(ends_with(web, words)) << option << "\n web: " << web << "\n words: " << words;
    EXPECT_TRUE(web.find("'" + field + "'") != std::string::npos || web.find("\"" + field + "\"") != std::string::npos)
        << "the web app names its field: " << web;
    EXPECT_EQ(web.find("--"), std::string::npos) << "no CLI option on the web: " << web;
  }
}

TEST_F(ServeAppTest, TheCliAndTheWebAppRefuseEveryBadReadOfTheTableWithTheSameWords) {
  const OJson table = parity_table();
  ASSERT_GE(table.at("reads").size(), 4u);
  for (const OJson& c : table.at("reads")) {
    const std::string option = c.at("option"), field = c.at("field"), words = c.at("words");
    const CliRun cli = run_gmwm({"wv", "recordings/imu.csv", option, c.at("value")}, dir_);
    EXPECT_EQ(cli.exit_code, 2) << option << ": " << cli.err;
    const std::string line = cli.err.substr(0, cli.err.find_last_not_of('\n') + 1);
    EXPECT_EQ(line.find('\n'), std::string::npos) << "one line: " << cli.err;
    EXPECT_NE(line.find(words), std::string::npos) << option << "\n cli: " << line << "\n words: " << words;

    const serve::HttpResponse r = post("/api/open", OJson{{"file", "imu.csv"}, {field, c.at("json")}});
    EXPECT_EQ(r.status, 400) << r.body;
    const std::string web = OJson::parse(r.body).value("error", std::string());
    EXPECT_NE(web.find(words), std::string::npos) << option << "\n web: " << web << "\n words: " << words;
    EXPECT_NE(web.find("\"" + field + "\""), std::string::npos) << "the web app names its field: " << web;
    EXPECT_EQ(web.find("--"), std::string::npos) << "no CLI option on the web: " << web;
  }
}

TEST_F(ServeAppTest, TheCliAndTheWebAppAcceptEveryGoodValueOfTheTableWithTheSameDocument) {
  const std::string d = open_imu();
  for (const OJson& c : parity_table().at("acceptances")) {
    const std::string study = c.at("study");
    std::vector<std::string> args = {study, "imu.csv", "--columns", "gyro_x"};
    for (const auto& [option, value] : c.at("options").items()) args.insert(args.end(), {option, value});
    OJson body = {{"dataset", d}, {"column", "gyro_x"}};
    for (const auto& [field, value] : c.at("json").items()) body[field] = value;
    const OJson web = run_job("/api/" + study, body);
    EXPECT_EQ(web.at("document"), cli_document(args, folder_)) << c.dump();
  }
}

}  // namespace
}  // namespace gmwm::test
