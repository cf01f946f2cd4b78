// io::OutputSet: outputs all or none, never over a device, FIFO, symlink or input; and
// io::GzipOutput past 4 GB.

#include "gmwm/io/output_set.h"

#include <gtest/gtest.h>
#include <fcntl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <functional>
#include <zlib.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "gmwm/engine/error.h"
#include "test_support.h"

namespace fs = std::filesystem;
using gmwm::InputError;
using gmwm::io::GzipOutput;
using gmwm::io::OutputSet;
using gmwm::io::OutputStream;

namespace {

class OutputSetTest : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = gmwm::test::temp_dir("output_set"); }
  void TearDown() override { fs::remove_all(dir_); }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  static void write(const std::string& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }
  static std::string read(const std::string& p) {
    std::ifstream f(p, std::ios::binary);
    std::ostringstream os;
    os << f.rdbuf();
    return os.str();
  }
  /// Every name in the folder (temporary files included).
  std::vector<std::string> names() const {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(dir_)) out.push_back(e.path().filename().string());
    std::sort(out.begin(), out.end());
    return out;
  }
  /// The InputError message of `f`, or "" when it did not throw.
  template <class F>
  static std::string error_of(F&& f) {
    try {
      f();
    } catch (const InputError& e) {
      return e.what();
    }
    return {};
  }

  fs::path dir_;
};

}  // namespace

TEST_F(OutputSetTest, StagedFilesAppearOnlyAtCommit) {
  OutputSet out;
  out.declare("--json", path("a.json"));
  out.declare("--csv", path("b.csv"));
  out.stage(path("a.json"), "{}\n");
  out.stage(path("b.csv"), "x\n1\n");
  EXPECT_FALSE(fs::exists(path("a.json")));
  EXPECT_FALSE(fs::exists(path("b.csv")));
  out.commit();
  EXPECT_EQ(read(path("a.json")), "{}\n");
  EXPECT_EQ(read(path("b.csv")), "x\n1\n");
  EXPECT_EQ(names(), (std::vector<std::string>{"a.json", "b.csv"})) << "no temporary file may remain";
}

TEST_F(OutputSetTest, ASetDestroyedWithoutCommitLeavesNoFileAndOldContentsIntact) {
  write(path("a.json"), "old");
  {
    OutputSet out;
    out.declare("--json", path("a.json"));
    out.declare("--csv", path("b.csv"));
    out.stage(path("a.json"), "new");
    out.stage(path("b.csv"), "new");
  }
  EXPECT_EQ(read(path("a.json")), "old");
  EXPECT_EQ(names(), std::vector<std::string>{"a.json"});
}

TEST_F(OutputSetTest, AFailedLaterStageLeavesEarlierTargetsUntouched) {
  write(path("a.json"), "old");
  std::string msg;
  {
    OutputSet out;
    out.declare("--json", path("a.json"));
    out.declare("--report", "/proc/gmwm-report.html");  // the folder exists, a file cannot be made there
    out.stage(path("a.json"), "new");
    msg = error_of([&] { out.stage("/proc/gmwm-report.html", "<html>"); });
  }
  EXPECT_NE(msg.find("cannot write '/proc/gmwm-report.html'"), std::string::npos) << msg;
  EXPECT_EQ(read(path("a.json")), "old");
  EXPECT_EQ(names(), std::vector<std::string>{"a.json"});
}

TEST_F(OutputSetTest, AProducerThatThrowsLeavesNoTemporaryFile) {
  OutputSet out;
  EXPECT_THROW(out.stage(path("a.csv"),
                         [](OutputStream& s) {
                           s.write("half");
                           throw InputError("the producer failed");
                         }),
               InputError);
  EXPECT_TRUE(names().empty());
  out.commit();  // nothing staged: nothing written
  EXPECT_TRUE(names().empty());
}

TEST_F(OutputSetTest, RefusesACharacterDeviceBeforeAnyWork) {
  OutputSet out;
  const std::string msg = error_of([&] { out.declare("--json", "/dev/null"); });
  EXPECT_NE(msg.find("--json '/dev/null': is a character device"), std::string::npos) << msg;
  EXPECT_NE(msg.find("'-' for standard output"), std::string::npos) << msg;
  struct stat st {};
  ASSERT_EQ(::stat("/dev/null", &st), 0);
  EXPECT_TRUE(S_ISCHR(st.st_mode));
}

TEST_F(OutputSetTest, RefusesAFifo) {
  ASSERT_EQ(::mkfifo(path("pipe").c_str(), 0600), 0);
  OutputSet out;
  const std::string msg = error_of([&] { out.declare("--csv", path("pipe")); });
  EXPECT_NE(msg.find("is a FIFO"), std::string::npos) << msg;
}

TEST_F(OutputSetTest, RefusesASymbolicLinkAndLeavesItsTargetAlone) {
  write(path("real.json"), "keep");
  fs::create_symlink("real.json", path("link.json"));
  OutputSet out;
  const std::string msg = error_of([&] { out.declare("--json", path("link.json")); });
  EXPECT_NE(msg.find("is a symbolic link to 'real.json'"), std::string::npos) << msg;
  EXPECT_TRUE(fs::is_symlink(path("link.json")));
  EXPECT_EQ(read(path("real.json")), "keep");
}

TEST_F(OutputSetTest, RefusesAFolder) {
  fs::create_directory(path("sub"));
  OutputSet out;
  EXPECT_NE(error_of([&] { out.declare("--json", path("sub")); }).find("is a folder"), std::string::npos);
  EXPECT_NE(error_of([&] { out.declare("--json", path("missing/a.json")); }).find("does not exist"), std::string::npos);
}

TEST_F(OutputSetTest, RefusesAnOutputThatIsAnInputUnderAnySpelling) {
  write(path("data.csv"), "x\n1\n");
  fs::create_hard_link(path("data.csv"), path("alias.csv"));
  OutputSet out;
  out.add_input(path("data.csv"));
  for (const std::string& p : {path("data.csv"), (dir_ / "." / "data.csv").string(), path("alias.csv")}) {
    const std::string msg = error_of([&] { out.declare("--csv", p); });
    EXPECT_NE(msg.find("is the input '" + path("data.csv") + "'"), std::string::npos) << p << ": " << msg;
  }
  EXPECT_EQ(read(path("data.csv")), "x\n1\n");
}

TEST_F(OutputSetTest, RefusesAnInputDeclaredAfterTheOutputThatNamesIt) {
  write(path("fit.json"), "{}");
  OutputSet out;
  out.declare("--output", path("fit.json"));
  const std::string msg = error_of([&] { out.add_input(path("fit.json")); });
  EXPECT_NE(msg.find("--output '" + path("fit.json") + "': is the input"), std::string::npos) << msg;
}

TEST_F(OutputSetTest, RefusesTwoOutputsNamingTheSameFile) {
  OutputSet out;
  out.declare("--output", path("x.csv"));
  const std::string msg = error_of([&] { out.declare("--json", (dir_ / "." / "x.csv").string()); });
  EXPECT_NE(msg.find("names the same file as --output"), std::string::npos) << msg;
  EXPECT_NO_THROW(out.declare("--output", path("x.csv"))) << "the same declaration twice is harmless";
}

TEST_F(OutputSetTest, AllowsStandardOutputOnce) {
  OutputSet out;
  out.declare("--json", "-");
  const std::string msg = error_of([&] { out.declare("--csv", "-"); });
  EXPECT_NE(msg.find("--json already writes to standard output"), std::string::npos) << msg;
}

TEST_F(OutputSetTest, CommitChecksTheTargetsAgainAndChangesNothingWhenOneBecameALink) {
  write(path("a.json"), "old");
  write(path("elsewhere"), "keep");
  OutputSet out;
  out.declare("--json", path("a.json"));
  out.declare("--csv", path("b.csv"));
  out.stage(path("a.json"), "new");
  out.stage(path("b.csv"), "new");
  fs::create_symlink("elsewhere", path("b.csv"));  // appears between staging and commit
  const std::string msg = error_of([&] { out.commit(); });
  EXPECT_NE(msg.find("is a symbolic link"), std::string::npos) << msg;
  EXPECT_EQ(read(path("a.json")), "old");
  EXPECT_EQ(read(path("elsewhere")), "keep");
}

TEST_F(OutputSetTest, KeepsAnExistingFilesPermissions) {
  write(path("a.json"), "old");
  ASSERT_EQ(::chmod(path("a.json").c_str(), 0640), 0);
  OutputSet out;
  out.stage(path("a.json"), "new");
  out.commit();
  struct stat st {};
  ASSERT_EQ(::stat(path("a.json").c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 07777, 0640u);
  EXPECT_EQ(read(path("a.json")), "new");
}

namespace {

/// Inflates what it receives and keeps the text's length and CRC-32 (nothing stored).
class InflatingCounter final : public OutputStream {
 public:
  InflatingCounter() {
    std::memset(&zs_, 0, sizeof zs_);
    inflateInit2(&zs_, 15 + 16);
    buf_.resize(1 << 20);
  }
  ~InflatingCounter() override { inflateEnd(&zs_); }
  void write(std::string_view bytes) override {
    zs_.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(bytes.data()));
    zs_.avail_in = static_cast<uInt>(bytes.size());  // the writer hands over at most 1 MB at a time
    while (zs_.avail_in > 0 && !ended) {
      zs_.next_out = buf_.data();
      zs_.avail_out = static_cast<uInt>(buf_.size());
      const int rc = inflate(&zs_, Z_NO_FLUSH);
      ASSERT_TRUE(rc == Z_OK || rc == Z_STREAM_END) << "inflate: " << rc;
      const std::size_t got = buf_.size() - zs_.avail_out;
      crc = crc32_z(crc, buf_.data(), got);
      text_bytes += got;
      ended = rc == Z_STREAM_END;
    }
  }
  std::uint64_t text_bytes = 0;
  uLong crc = crc32_z(0, nullptr, 0);
  bool ended = false;

 private:
  z_stream zs_;
  std::vector<unsigned char> buf_;
};

}  // namespace

TEST_F(OutputSetTest, GzipOutputPastFourGigabytesInflatesToEveryByte) {
  // 4.3e9 bytes: past 2^32, where a 32-bit length wraps (the old writer kept
  // size mod 2^32 and cut the last number).
  std::string block;
  for (int i = 0; block.size() < (1u << 20); ++i) block += std::to_string(i * 0.001 - 3.5) + ",42\n";
  const std::uint64_t target = 4'300'000'000ull;
  InflatingCounter sink;
  GzipOutput gz(sink, "big.csv.gz", 0);  // stored blocks: the length bookkeeping is what is tested
  std::uint64_t written = 0;
  uLong crc = crc32_z(0, nullptr, 0);
  while (written < target) {
    const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(block.size(), target - written));
    gz.write(std::string_view(block.data(), n));
    crc = crc32_z(crc, reinterpret_cast<const Bytef*>(block.data()), n);
    written += n;
  }
  gz.finish();
  EXPECT_TRUE(sink.ended) << "the gzip trailer must be written";
  EXPECT_EQ(sink.text_bytes, target);
  EXPECT_EQ(sink.crc, crc);
}

namespace {

// Runs `child` in a forked process (no core dump, the signals at their default action) and
// returns its wait status.
template <class F>
int in_child(F&& child) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    const rlimit none{0, 0};
    ::setrlimit(RLIMIT_CORE, &none);
    // A runner that ignores these (nohup, a CI job in the background) passes that on to its
    // children; the library rightly leaves an ignored signal alone, so the test restores the
    // default of an ignored one. Only an ignored one: a handler the library installed in this
    // process before the fork (an earlier test of the same run) must stay, as the library
    // installs its handlers once per process.
    for (const int sig : {SIGHUP, SIGINT, SIGQUIT, SIGTERM}) {
      struct sigaction current {};
      if (::sigaction(sig, nullptr, &current) == 0 && !(current.sa_flags & SA_SIGINFO) && current.sa_handler == SIG_IGN)
        std::signal(sig, SIG_DFL);
    }
    child();
    ::_exit(0);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  return status;
}

// A producer that writes 4 MB, then delivers `sig` to its own process.
std::function<void(OutputStream&)> killed_midway(int sig) {
  return [sig](OutputStream& s) {
    const std::string block(1 << 20, 'x');
    for (int i = 0; i < 4; ++i) s.write(block);
    ::kill(::getpid(), sig);
    ::_exit(3);  // not reached when the signal ends the process
  };
}

}  // namespace

TEST_F(OutputSetTest, StagedFilesAreUnnamedUntilCommitAndNoSignalLeavesThemBehind) {
  // SIGKILL cannot be caught: only an unnamed (O_TMPFILE) staged file is sure to vanish.
  const int probe = ::open(dir_.c_str(), O_TMPFILE | O_RDWR, 0600);
  if (probe < 0) GTEST_SKIP() << "no O_TMPFILE in " << dir_ << ": " << std::strerror(errno);
  ::close(probe);
  for (int sig : {SIGKILL, SIGQUIT, SIGALRM, SIGTERM}) {
    write(path("old.csv"), "old");
    const int status = in_child([&] {
      OutputSet out;
      out.declare("--csv", path("old.csv"));
      out.declare("--json", path("new.json"));
      out.stage(path("new.json"), "{}");
      // Nothing of a staged file is visible in the folder.
      if (names() != std::vector<std::string>{"old.csv"}) ::_exit(4);
      out.stage(path("old.csv"), killed_midway(sig));
    });
    ASSERT_TRUE(WIFSIGNALED(status)) << "signal " << sig << ": status " << status;
    EXPECT_EQ(WTERMSIG(status), sig);
    EXPECT_EQ(names(), std::vector<std::string>{"old.csv"}) << "signal " << sig;
    EXPECT_EQ(read(path("old.csv")), "old");
  }
}

TEST_F(OutputSetTest, NamedStagingIsRemovedOnEveryCatchableSignal) {
  // Where the filesystem has no O_TMPFILE: named files, removed by the signal handler.
  for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGPIPE, SIGQUIT, SIGALRM}) {
    struct sigaction current {};
    ::sigaction(sig, nullptr, &current);
    if (current.sa_handler == SIG_IGN) continue;  // ignored by whoever started the test: nothing to remove
    write(path("old.csv"), "old");
    const int status = in_child([&] {
      OutputSet out;
      out.force_named_staging();
      out.declare("--csv", path("old.csv"));
      out.declare("--json", path("new.json"));
      out.stage(path("new.json"), "{}");
      if (names().size() != 2) ::_exit(4);  // the named staged file is there
      out.stage(path("old.csv"), killed_midway(sig));
    });
    ASSERT_TRUE(WIFSIGNALED(status)) << "signal " << sig << ": status " << status;
    EXPECT_EQ(WTERMSIG(status), sig);
    EXPECT_EQ(names(), std::vector<std::string>{"old.csv"}) << "signal " << sig;
    EXPECT_EQ(read(path("old.csv")), "old");
  }
}

TEST_F(OutputSetTest, NamedStagingCommitsLikeUnnamedStaging) {
  write(path("a.json"), "old");
  OutputSet out;
  out.force_named_staging();
  out.declare("--json", path("a.json"));
  out.declare("--csv", path("b.csv"));
  out.stage(path("a.json"), "new");
  out.stage(path("b.csv"), "x\n");
  out.commit();
  EXPECT_EQ(read(path("a.json")), "new");
  EXPECT_EQ(read(path("b.csv")), "x\n");
  EXPECT_EQ(names(), (std::vector<std::string>{"a.json", "b.csv"}));
}
