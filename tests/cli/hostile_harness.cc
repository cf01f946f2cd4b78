#include "hostile_harness.h"

#include <sys/resource.h>

#include <cctype>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iterator>

#include "test_support.h"

namespace fs = std::filesystem;

namespace gmwm::test::hostile {

std::string base_csv() {
  std::string s = "time,gyro_x,accel_x\n";
  for (int i = 0; i < 4096; ++i)
    s += std::to_string(i * 0.01) + "," + std::to_string(std::sin(i * 0.37) * 1e-3 + (i % 7) * 1e-4) + "," +
         std::to_string(9.81 + std::cos(i * 0.11) * 1e-2) + "\n";
  return s;
}

std::string bytes(std::initializer_list<int> b) {
  std::string s;
  for (int c : b) s += static_cast<char>(c);
  return s;
}

std::string gzip_bomb(const std::string& head, const std::string& unit, int copies) {
  std::string body;
  while (body.size() < (std::size_t{1} << 20)) body += unit;
  std::string out = gzip_member(head);
  const std::string member = gzip_member(body);
  for (int i = 0; i < copies; ++i) out += member;
  return out;
}

Setup file(const std::string& name, const std::string& text) {
  return [=](const fs::path& d) { write_text(d / name, text); };
}

Setup both(Setup a, Setup b) {
  return [=](const fs::path& d) { a(d), b(d); };
}

std::map<std::string, std::string> snapshot(const fs::path& dir) {
  std::map<std::string, std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) {
    std::error_code ec;
    if (e.is_symlink(ec)) {
      out[e.path().filename().string()] = "<symlink>";
    } else if (e.is_regular_file(ec)) {
      std::ifstream in(e.path(), std::ios::binary);
      out[e.path().filename().string()] = std::string(std::istreambuf_iterator<char>(in), {});
    } else {
      out[e.path().filename().string()] = "<special>";
    }
  }
  return out;
}

void expect_contract(const Case& c) {
  const fs::path dir = temp_dir("hostile");
  if (c.setup) c.setup(dir);
  const auto before = snapshot(dir);
  const auto t0 = std::chrono::steady_clock::now();
  const CliRun r = run_gmwm(c.args, dir, c.how);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  rusage usage{};
  ::getrusage(RUSAGE_CHILDREN, &usage);  // the largest descendant so far: this case's at most

  EXPECT_EQ(r.exit_code, 2) << r.err;
  const auto lines = lines_of(r.err);
  ASSERT_EQ(lines.size(), 1u) << r.err;
  EXPECT_EQ(lines[0].rfind("gmwm: error: ", 0), 0u) << lines[0];
  for (const auto& m : c.mentions) EXPECT_NE(lines[0].find(m), std::string::npos) << "'" << m << "' in: " << lines[0];
  EXPECT_TRUE(r.out.empty()) << r.out;
  EXPECT_EQ(snapshot(dir), before) << "a file was created or changed";
  EXPECT_LT(seconds, kMaxSeconds);
  EXPECT_LT(usage.ru_maxrss * 1024L, kMaxRssBytes);
  fs::remove_all(dir);
}

std::string test_name(const std::string& text) {
  std::string name;
  bool up = true;
  for (char ch : text) {
    if (std::isalnum(static_cast<unsigned char>(ch))) {
      name += up ? static_cast<char>(std::toupper(static_cast<unsigned char>(ch))) : ch;
      up = false;
    } else {
      up = true;
    }
  }
  return name;
}

}  // namespace gmwm::test::hostile
