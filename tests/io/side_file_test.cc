// io::SideFile (side_file.h): a pipe peeked keeps its bytes, the size limit holds for files
// and pipes, devices and folders are refused by name.
#include "gmwm/io/side_file.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "gmwm/engine/error.h"
#include "test_support.h"

namespace fs = std::filesystem;
using gmwm::InputError;
using gmwm::io::SideFile;

namespace {

template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return {};
}

// A pipe holding `text` with its writer closed, as a path (/proc/self/fd/N).
struct FilledPipe {
  int fds[2] = {-1, -1};
  explicit FilledPipe(const std::string& text) {
    EXPECT_EQ(::pipe(fds), 0);
    EXPECT_EQ(::write(fds[1], text.data(), text.size()), static_cast<ssize_t>(text.size()));
    ::close(fds[1]);
  }
  ~FilledPipe() { ::close(fds[0]); }
  std::string path() const { return "/proc/self/fd/" + std::to_string(fds[0]); }
};

}  // namespace

TEST(SideFile, APeekedPipeStillHoldsEveryByte) {
  FilledPipe p("{\"tool\": \"gmwm\"}");
  SideFile f(p.path(), "a JSON document");
  EXPECT_TRUE(f.is_pipe());
  EXPECT_EQ(f.peek(5), "{\"too");
  EXPECT_EQ(f.peek(100), "{\"tool\": \"gmwm\"}");  // all there is: the writer is gone
  EXPECT_EQ(f.read(), "{\"tool\": \"gmwm\"}");
}

TEST(SideFile, ThePeekOfAPipeLeavesItForAnotherReaderOfTheSamePath) {
  FilledPipe p("time,x\n0,1\n");
  {
    SideFile f(p.path(), "data");
    EXPECT_EQ(f.peek(4), "time");
  }
  EXPECT_EQ(SideFile(p.path(), "data").read(), "time,x\n0,1\n");
}

TEST(SideFile, RefusesMoreThanItsLimitFromAFileOrAPipe) {
  const fs::path dir = gmwm::test::temp_dir("side_file");
  std::ofstream(dir / "big.yaml") << std::string(2000, '#');
  const std::string f =
      error_of([&] { gmwm::io::read_side_file((dir / "big.yaml").string(), "a Kalibr imu.yaml", 1024); });
  EXPECT_NE(f.find("big.yaml: holds more than 1024 bytes, expected a Kalibr imu.yaml"), std::string::npos) << f;
  FilledPipe p(std::string(2000, '#'));
  const std::string q = error_of([&] { gmwm::io::read_side_file(p.path(), "a Kalibr imu.yaml", 1024); });
  EXPECT_NE(q.find("holds more than 1024 bytes"), std::string::npos) << q;
  EXPECT_EQ(gmwm::io::read_side_file((dir / "big.yaml").string(), "x", 2000).size(),
            2000u);  // the limit itself is fine
  fs::remove_all(dir);
}

TEST(SideFile, RefusesDevicesFoldersAndMissingFilesByName) {
  EXPECT_NE(error_of([] {
              SideFile("/dev/zero", "a Kalibr imu.yaml");
            }).find("/dev/zero: is a character device, expected a Kalibr imu.yaml (a regular file or a pipe)"),
            std::string::npos);
  EXPECT_NE(error_of([] { SideFile("/", "a Gazebo SDF file"); }).find("/: is a folder"), std::string::npos);
  EXPECT_NE(error_of([] {
              SideFile("/nonexistent/x.json", "a result");
            }).find("/nonexistent/x.json: file not found, expected a result"),
            std::string::npos);
}
