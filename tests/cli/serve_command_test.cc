// gmwm serve as a user starts it: it prints its address, answers there, and stops cleanly
// on SIGTERM (its uploads removed); bad options are exit 2 with one line.

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "cli_runner.h"
#include "test_support.h"

namespace {

namespace fs = std::filesystem;
using gmwm::test::run_gmwm;

// GET `path` on 127.0.0.1:port with one connection and the given header lines; the whole answer.
std::string http_get(int port, const std::string& path, const std::string& headers) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(static_cast<std::uint16_t>(port));
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  std::string answer;
  if (::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0) {
    const std::string request = "GET " + path + " HTTP/1.1\r\n" + headers + "Connection: close\r\n\r\n";
    if (::send(fd, request.data(), request.size(), MSG_NOSIGNAL) == static_cast<ssize_t>(request.size())) {
      char buf[4096];
      for (ssize_t k; (k = ::recv(fd, buf, sizeof buf, 0)) > 0;) answer.append(buf, static_cast<std::size_t>(k));
    }
  }
  ::close(fd);
  return answer;
}

class GmwmServe : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = gmwm::test::temp_dir("cli_serve"); }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(GmwmServe, PrintsItsLoopbackAddressAnswersThereAndStopsOnSigterm) {
  gmwm::test::write_noise_csv(dir_ / "x.csv", 1024, "gyro_x");
  int out[2];
  ASSERT_EQ(::pipe(out), 0);
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::dup2(out[1], 1);
    ::close(out[0]);
    const int null = ::open("/dev/null", O_RDWR);
    ::dup2(null, 0), ::dup2(null, 2);
    ::execl(gmwm::test::gmwm_cli_path(), gmwm::test::gmwm_cli_path(), "serve", dir_.c_str(), "--port", "0",
            static_cast<char*>(nullptr));
    ::_exit(127);
  }
  ASSERT_GT(pid, 0);
  ::close(out[1]);
  std::string line;
  char c;
  while (::read(out[0], &c, 1) == 1 && c != '\n') line += c;
  ASSERT_EQ(line.rfind("gmwm serve: http://127.0.0.1:", 0), 0u) << line;
  const std::string url = line.substr(12, line.find(' ', 12) - 12);
  // http://127.0.0.1:PORT/?token=T: a fresh 128-bit token.
  const int port = std::stoi(url.substr(url.rfind(':') + 1));
  const std::string token = url.substr(url.find("?token=") + 7);
  EXPECT_EQ(url, "http://127.0.0.1:" + std::to_string(port) + "/?token=" + token);
  EXPECT_EQ(token.size(), 32u) << url;
  const std::string host = "Host: 127.0.0.1:" + std::to_string(port) + "\r\n";
  // The folder's listing answers at that address, to a request with the token.
  const std::string answer = http_get(port, "/api/files", host + "X-Gmwm-Token: " + token + "\r\n");
  EXPECT_EQ(answer.rfind("HTTP/1.1 200", 0), 0u) << answer;
  EXPECT_NE(answer.find("\"path\": \"x.csv\""), std::string::npos) << answer;
  // Without it, or through another name, nothing of the folder.
  for (const std::string& headers :
       {host, "Host: evil.example:" + std::to_string(port) + "\r\nX-Gmwm-Token: " + token + "\r\n"}) {
    const std::string refused = http_get(port, "/api/files", headers);
    EXPECT_TRUE(refused.rfind("HTTP/1.1 401", 0) == 0 || refused.rfind("HTTP/1.1 403", 0) == 0) << refused;
    EXPECT_EQ(refused.find("x.csv"), std::string::npos) << refused;
  }
  ::kill(pid, SIGTERM);
  int status = 0;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (::waitpid(pid, &status, WNOHANG) == 0 && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  ASSERT_TRUE(WIFEXITED(status)) << "gmwm serve did not stop on SIGTERM";
  EXPECT_EQ(WEXITSTATUS(status), 0);
  ::close(out[0]);
}

TEST_F(GmwmServe, SaysAtStartThatThePageWillShowNoPlotsWhenVegaCannotBeRead) {
  // stdout and stderr to one pipe; Vega's folder pointed at one that does not exist.
  int out[2];
  ASSERT_EQ(::pipe(out), 0);
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::dup2(out[1], 1), ::dup2(out[1], 2);
    ::close(out[0]);
    ::setenv("GMWM_VEGA_DIR", "/nonexistent-vega-folder", 1);
    ::execl(gmwm::test::gmwm_cli_path(), gmwm::test::gmwm_cli_path(), "serve", dir_.c_str(), "--port", "0",
            static_cast<char*>(nullptr));
    ::_exit(127);
  }
  ASSERT_GT(pid, 0);
  ::close(out[1]);
  std::string text;
  char c;
  while (text.find("no plots") == std::string::npos || text.back() != '\n') {
    if (::read(out[0], &c, 1) != 1) break;
    text += c;
  }
  EXPECT_NE(text.find("gmwm: warning: the page will show no plots (its tables, numbers and exports work)"),
            std::string::npos)
      << text;
  const auto at = text.find("http://127.0.0.1:");
  ASSERT_NE(at, std::string::npos) << text;
  const std::string url = text.substr(at, text.find(' ', at) - at);
  const int port = std::stoi(url.substr(url.rfind(':') + 1));
  const std::string token = url.substr(url.find("?token=") + 7);
  const std::string vega = http_get(port, "/vega.js", "Host: 127.0.0.1:" + std::to_string(port) + "\r\n");
  EXPECT_EQ(vega.rfind("HTTP/1.1 404", 0), 0u) << vega;
  EXPECT_NE(vega.find("built without Vega"), std::string::npos) << vega;
  ::kill(pid, SIGTERM);
  int status = 0;
  ::waitpid(pid, &status, 0);
  ::close(out[0]);
}

TEST_F(GmwmServe, RefusesAFolderThatIsNotOneAndABadPortWithOneLine) {
  auto r = run_gmwm({"serve", "no-such-folder", "--port", "0"}, dir_);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("FOLDER 'no-such-folder'"), std::string::npos) << r.err;
  EXPECT_EQ(gmwm::test::lines_of(r.err).size(), 1u) << r.err;
  r = run_gmwm({"serve", ".", "--port", "70000"}, dir_);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--port"), std::string::npos) << r.err;
  r = run_gmwm({"serve", ".", "--port", "0", "--host", "203.0.113.7"}, dir_);
  EXPECT_EQ(r.exit_code, 2) << "an address of no interface here cannot be bound";
  EXPECT_NE(r.err.find("has the token"), std::string::npos) << "warned first: " << r.err;
  EXPECT_NE(r.err.find("cannot listen on 203.0.113.7"), std::string::npos) << r.err;
  // A token chosen by a script must be one nobody guesses.
  r = run_gmwm({"serve", ".", "--port", "0"}, dir_, {.before = "GMWM_SERVE_TOKEN=abc"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("GMWM_SERVE_TOKEN: expected at least 16"), std::string::npos) << r.err;
  EXPECT_EQ(gmwm::test::lines_of(r.err).size(), 1u) << r.err;
  r = run_gmwm({"serve", ".", "--port", "0", "--allow-host", "a b"}, dir_);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--allow-host: found 'a b'"), std::string::npos) << r.err;
}

}  // namespace
