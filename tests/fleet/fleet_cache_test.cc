// The fleet's cache verifies each entry it reads back (fleet/fleet_cache.h, issue 42 item 11):
// an entry holds its key and the SHA-256 of its key and record, so an entry edited by hand,
// cut short, copied under another key's name or of another format is not used, and `load`
// says why, naming the entry's file.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "gmwm/fleet/fleet_cache.h"
#include "gmwm/fleet/fleet_record.h"
#include "test_support.h"

namespace fs = std::filesystem;
using namespace gmwm::fleet;

namespace {

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

void write_text(const fs::path& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

class FleetCacheTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = gmwm::test::temp_dir("fleet_cache");
    key_ = text_sha256("recording one");
    other_ = text_sha256("recording two");
    FleetRecord r;
    r.freq = 100.0;
    r.seconds = 0.25;
    record_ = fleet_record_text(r);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string entry(const std::string& key) const { return (dir_ / (key + ".json")).string(); }

  fs::path dir_;
  std::string key_, other_, record_;
};

TEST_F(FleetCacheTest, AnEntryReadsBackAsStoredUnderItsKeyWithAHeaderLineFirst) {
  const FleetCache cache(dir_.string());
  cache.store(key_, record_);
  std::string why;
  const auto back = cache.load(key_, &why);
  ASSERT_TRUE(back.has_value()) << why;
  EXPECT_EQ(*back, record_);
  EXPECT_TRUE(why.empty()) << why;
  // The record's text follows the header line as it was computed.
  const std::string text = read_text(entry(key_));
  const auto nl = text.find('\n');
  ASSERT_NE(nl, std::string::npos);
  EXPECT_EQ(text.substr(nl + 1), record_);
  EXPECT_NE(text.substr(0, nl).find("\"key\":\"" + key_ + "\""), std::string::npos) << text.substr(0, nl);
}

TEST_F(FleetCacheTest, NoEntryIsNothingToSay) {
  std::string why;
  EXPECT_FALSE(FleetCache(dir_.string()).load(key_, &why).has_value());
  EXPECT_TRUE(why.empty()) << why;
}

TEST_F(FleetCacheTest, AnEntryWithANumberEditedIsNotUsedAndTheReasonNamesItsFile) {
  const FleetCache cache(dir_.string());
  cache.store(key_, record_);
  std::string text = read_text(entry(key_));
  const auto at = text.find("\"freq\":100.0");
  ASSERT_NE(at, std::string::npos) << text;
  text.replace(at, 12, "\"freq\":900.0");  // the same length: only the digest tells
  write_text(entry(key_), text);
  std::string why;
  EXPECT_FALSE(cache.load(key_, &why).has_value());
  EXPECT_EQ(why.rfind(entry(key_) + ": ", 0), 0u) << why;
  EXPECT_NE(why.find("SHA-256"), std::string::npos) << why;
  EXPECT_NE(why.find("edited"), std::string::npos) << why;
}

TEST_F(FleetCacheTest, AnEntryCopiedUnderAnotherKeysNameIsNotUsed) {
  const FleetCache cache(dir_.string());
  cache.store(key_, record_);
  fs::copy_file(entry(key_), entry(other_));
  std::string why;
  EXPECT_FALSE(cache.load(other_, &why).has_value());
  EXPECT_EQ(why.rfind(entry(other_) + ": ", 0), 0u) << why;
  EXPECT_NE(why.find("another key (" + key_.substr(0, 12) + "...)"), std::string::npos) << why;
  // Its header rewritten to the other key (without the digest's): still not used.
  std::string text = read_text(entry(other_));
  text.replace(text.find(key_), key_.size(), other_);
  write_text(entry(other_), text);
  EXPECT_FALSE(cache.load(other_, &why).has_value());
  EXPECT_NE(why.find("SHA-256"), std::string::npos) << why;
}

TEST_F(FleetCacheTest, AnEntryCutShortIsNotUsedWhereverItIsCut) {
  const FleetCache cache(dir_.string());
  cache.store(key_, record_);
  const std::string whole = read_text(entry(key_));
  const auto nl = whole.find('\n');
  for (std::size_t keep : {whole.size() - 1, nl + 1 + record_.size() / 2, nl + 1, nl, nl / 2, std::size_t{0}}) {
    write_text(entry(key_), whole.substr(0, keep));
    std::string why;
    EXPECT_FALSE(cache.load(key_, &why).has_value()) << keep;
    EXPECT_EQ(why.rfind(entry(key_) + ": ", 0), 0u) << keep << ": " << why;
    if (keep > nl) EXPECT_NE(why.find("cut short"), std::string::npos) << keep << ": " << why;
  }
}

TEST_F(FleetCacheTest, AnEntryWithoutAHeaderOrOfAnotherFormatIsNotUsed) {
  const FleetCache cache(dir_.string());
  std::string why;
  write_text(entry(key_), record_);  // the bare record (the cache before its entries verified)
  EXPECT_FALSE(cache.load(key_, &why).has_value());
  EXPECT_NE(why.find("found no header line of a gmwm fleet cache entry"), std::string::npos) << why;
  cache.store(key_, record_);
  std::string text = read_text(entry(key_));
  text.replace(text.find("\"gmwm_fleet_cache\":1"), 20, "\"gmwm_fleet_cache\":7");
  write_text(entry(key_), text);
  EXPECT_FALSE(cache.load(key_, &why).has_value());
  EXPECT_NE(why.find("found cache format 7, expected 1"), std::string::npos) << why;
}

TEST_F(FleetCacheTest, AFolderInAnEntrysPlaceIsNotUsed) {
  fs::create_directories(entry(key_));
  std::string why;
  EXPECT_FALSE(FleetCache(dir_.string()).load(key_, &why).has_value());
  EXPECT_EQ(why.rfind(entry(key_) + ": found a folder, link or special file", 0), 0u) << why;
}

}  // namespace
