// The bad-input contract (hostile_harness.h) over crafted binary logs (issue 25): PX4 ULog,
// ROS 1 bags, MCAP files and rosbag2 databases whose size fields are driven to overflow, whose
// chunks (none, bz2, lz4, zstd) claim more than they hold or inflate past the limits. Each
// case exits 2 with one line naming the file, the place (byte offset, or topic and message
// index) and what was expected, writes nothing and stays under 10 s and 1 GB. The files are
// written by tests/support/log_writers.h from the published formats, then tampered with.
#include <cstdint>
#include <algorithm>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <sqlite3.h>
#include <sys/stat.h>
#include <unistd.h>

#include "hostile_harness.h"
#include "log_writers.h"
#include "test_support.h"

namespace fs = std::filesystem;
using namespace gmwm::test::hostile;
using gmwm::test::LeBytes;
using gmwm::test::patch;

namespace {

std::string at(std::uint64_t offset) { return "byte " + std::to_string(offset); }

// The offset of the value of header field `name` ("name=") in `bag`, searched from `from`.
std::uint64_t field_value(const std::string& bag, std::uint64_t from, const std::string& name) {
  const auto p = bag.find(name + "=", from);
  EXPECT_NE(p, std::string::npos) << name;
  return p + name.size() + 1;
}

// Where a ROS 1 record's data start (after its header and the data length).
std::uint64_t record_data(const std::string& bag, std::uint64_t record) {
  std::uint32_t header = 0;
  std::memcpy(&header, bag.data() + record, 4);
  return record + 4 + header + 4;
}

// A ULog whose sensor_combined nests arrays to 2^64 - 2^40 + 48 bytes: in size_t the format
// wraps around to 48 bytes, a data message of 48 bytes passes the size check, and gyro_rad's
// offset is 2^40 + 8 (the reader read there: SIGSEGV).
std::string ulog_wrapping_format() {
  gmwm::test::UlogBuilder u;
  u.format("t1:uint8_t[65536] a;");  // 2^16 bytes
  u.format("t2:t1[65536] a;");       // 2^32
  u.format("t3:t2[65536] a;");       // 2^48
  u.format(
      "sensor_combined:uint64_t timestamp;t2[256] pad;float[3] gyro_rad;uint32_t gyro_integral_dt;"
      "int32_t accelerometer_timestamp_relative;float[3] accelerometer_m_s2;uint32_t accelerometer_integral_dt;"
      "uint32_t flags;t3[65535] wrap1;t2[65280] wrap2;");
  u.subscribe(0, 0, "sensor_combined");
  for (int i = 0; i < 32; ++i)
    u.data(0, LeBytes().put(std::uint64_t{1000} * static_cast<std::uint64_t>(i + 1)).b + std::string(40, '\1'));
  return u.bytes;
}

std::vector<Case> corpus() {
  std::vector<Case> c;
  // --- PX4 ULog: formats and message sizes --------------------------------------------------
  {
    c.push_back({"ULog format sizes that wrap around 2^64",
                 {"wv", "wrap.ulg"},
                 {"wrap.ulg", "message 5 at byte", "format 't1'", "larger than 65533 bytes"},
                 file("wrap.ulg", ulog_wrapping_format())});
    gmwm::test::UlogBuilder self;
    self.format("loop:uint64_t timestamp;loop inner;").format("sensor_combined:uint64_t timestamp;loop l;");
    self.subscribe(0, 0, "sensor_combined");
    c.push_back({"ULog format that contains itself",
                 {"wv", "self.ulg"},
                 {"self.ulg", "message 3 at byte", "format 'loop' nests deeper than 16"},
                 file("self.ulg", self.bytes)});
    gmwm::test::UlogBuilder array;
    array.format("sensor_combined:uint64_t timestamp;float[18446744073709551615] gyro_rad;");
    array.subscribe(0, 0, "sensor_combined");
    c.push_back({"ULog array length of 2^64 - 1",
                 {"wv", "array.ulg"},
                 {"array.ulg", "message 2 at byte", "bad array length, expected [1..999999]"},
                 file("array.ulg", array.bytes)});
    std::string cut = gmwm::test::ulog_sensor_combined(64);
    patch(cut, cut.size() - 53, std::uint16_t{0xffff});  // the last message (3 + 2 + 48 bytes) claims 65535
    c.push_back({"ULog message size past the end",
                 {"wv", "cut.ulg"},
                 {"cut.ulg", "at byte " + std::to_string(cut.size() - 53), "a 'D' message of 65535 bytes with 50 left"},
                 file("cut.ulg", cut)});
    gmwm::test::UlogBuilder shortd;
    shortd.bytes = gmwm::test::ulog_sensor_combined(20);
    shortd.data(0, std::string(6, '\0'));
    c.push_back({"ULog data shorter than its format",
                 {"wv", "short.ulg"},
                 {"short.ulg", "message 23 at byte", "data of 6 bytes, expected 48"},
                 file("short.ulg", shortd.bytes)});
    gmwm::test::UlogBuilder shorta;
    shorta.add('A', std::string(2, '\0'));
    c.push_back({"ULog subscription shorter than its fields",
                 {"wv", "a.ulg"},
                 {"a.ulg", "message 1 at byte 16", "an 'A' message shorter than 4 bytes"},
                 file("a.ulg", shorta.bytes)});
  }
  // --- ROS 1 bags: record, header, index and chunk sizes ------------------------------------
  {
    const gmwm::test::Ros1Bag bag = gmwm::test::ros1_bag();
    std::string header_len = bag.bytes;
    patch(header_len, 13, std::uint32_t{0xffffffff});
    c.push_back({"ROS bag record header length 2^32 - 1",
                 {"wv", "h.bag"},
                 {"h.bag", "record at byte 13", "header length 4294967295 runs past the end of the file"},
                 file("h.bag", header_len)});
    std::string data_len = bag.bytes;
    std::uint32_t h = 0;
    std::memcpy(&h, bag.bytes.data() + 13, 4);
    patch(data_len, 13 + 4 + h, std::uint32_t{0xfffffff0});
    c.push_back({"ROS bag record data length 2^32 - 16",
                 {"wv", "d.bag"},
                 {"d.bag", "record at byte 13", "data of 4294967280 bytes runs past the end of the file"},
                 file("d.bag", data_len)});
    std::string index_pos = bag.bytes;
    patch(index_pos, field_value(bag.bytes, 13, "index_pos"), ~std::uint64_t{0});
    c.push_back({"ROS bag index_pos 2^64 - 1",
                 {"wv", "i.bag"},
                 {"i.bag", "index_pos 18446744073709551615 is outside the file"},
                 file("i.bag", index_pos)});
    std::string chunk_pos = bag.bytes;
    patch(chunk_pos, field_value(bag.bytes, bag.chunk_info_at[1], "chunk_pos"), std::uint64_t{1} << 63);
    c.push_back({"ROS bag chunk_pos 2^63",
                 {"wv", "c.bag"},
                 {"c.bag", "record at byte 9223372036854775808", "truncated (the file ends inside it)"},
                 file("c.bag", chunk_pos)});
    std::string count = bag.bytes;
    patch(count, field_value(bag.bytes, bag.chunk_info_at[0], "count"), std::uint32_t{0x20000000});
    c.push_back({"ROS bag chunk info count 2^29",
                 {"wv", "n.bag"},
                 {"n.bag", "chunk info record at " + at(bag.chunk_info_at[0]), "is malformed"},
                 file("n.bag", count)});
    std::string inner = bag.bytes;
    const std::uint64_t records = record_data(bag.bytes, bag.chunk_pos[0]);
    patch(inner, records, std::uint32_t{0xfffffff0});
    c.push_back({"ROS bag record inside a chunk with a header of 2^32 - 16 bytes",
                 {"wv", "r.bag"},
                 {"r.bag", "chunk at " + at(bag.chunk_pos[0]) + ", record at 0 of it",
                  "its header of 4294967280 bytes runs past the chunk's"},
                 file("r.bag", inner)});
    std::string frame = bag.bytes;
    patch(frame, records + bag.first_message_data_at + 12, std::uint32_t{0xffffffff});
    c.push_back(
        {"ROS bag message frame_id of 2^32 - 1 bytes",
         {"wv", "f.bag"},
         {"f.bag", "topic /imu message 1", "frame_id (a string of 4294967295 bytes at byte 16) runs past its end"},
         file("f.bag", frame)});
  }
  // --- MCAP: record lengths, chunk fields, strings, CDR ------------------------------------------
  {
    gmwm::test::McapOptions o;
    o.crc = false;  // the tampered records are then read, not refused by their CRC
    const gmwm::test::Mcap m = gmwm::test::mcap_file(o);
    std::string len = m.bytes;
    patch(len, 9, ~std::uint64_t{0});
    c.push_back({"MCAP record length 2^64 - 1",
                 {"wv", "l.mcap"},
                 {"l.mcap", "record at byte 8", "record of 18446744073709551615 bytes runs past the end of the file"},
                 file("l.mcap", len)});
    std::string records_len = m.bytes;
    patch(records_len, m.chunk_at[0] + 9 + 28 + 4, ~std::uint64_t{0});
    c.push_back({"MCAP chunk records length 2^64 - 1",
                 {"wv", "c.mcap"},
                 {"c.mcap", "record at " + at(m.chunk_at[0]),
                  "malformed chunk record: its records (18446744073709551615 bytes"},
                 file("c.mcap", records_len)});
    std::string compression = m.bytes;
    patch(compression, m.chunk_at[0] + 9 + 28, std::uint32_t{0xffffffff});
    c.push_back({"MCAP chunk compression string of 2^32 - 1 bytes",
                 {"wv", "s.mcap"},
                 {"s.mcap", "record at " + at(m.chunk_at[0]), "its compression (a string of 4294967295 bytes"},
                 file("s.mcap", compression)});
    std::string inner = m.bytes;
    patch(inner, m.chunk_at[0] + 9 + 28 + 4 + 8 + 1, std::uint64_t{1} << 63);
    c.push_back({"MCAP record inside a chunk of 2^63 bytes",
                 {"wv", "i.mcap"},
                 {"i.mcap", "chunk at " + at(m.chunk_at[0]) + ", record at byte 0 of its records",
                  "record of 9223372036854775808 bytes runs past the end of the chunk"},
                 file("i.mcap", inner)});
    std::string topic = m.bytes;
    patch(topic, topic.find("/imu") - 4, std::uint32_t{0xfffffffe});
    c.push_back({"MCAP channel topic of 2^32 - 2 bytes",
                 {"wv", "t.mcap"},
                 {"t.mcap", "malformed channel record: its topic (a string of 4294967294 bytes"},
                 file("t.mcap", topic)});
    std::string cdr = m.bytes;
    patch(cdr, cdr.find(std::string("\x04\x00\x00\x00imu\x00", 8)), std::uint32_t{0xffffffff});
    c.push_back(
        {"MCAP CDR frame_id of 2^32 - 1 bytes",
         {"wv", "cdr.mcap"},
         {"cdr.mcap", "topic /imu message 1", "frame_id (a string of 4294967295 bytes at byte 16) runs past its end"},
         file("cdr.mcap", cdr)});
    gmwm::test::McapOptions flat = o;
    flat.per_chunk = 0;
    flat.messages = 20;
    std::string shortm = gmwm::test::mcap_file(flat).bytes;
    const std::uint64_t content = 2 + 4 + 8 + 8 + gmwm::test::imu_cdr(0, o.step_ns).size();
    const std::uint64_t first_message = shortm.find(LeBytes().put(std::uint8_t{0x05}).put(content).b);
    patch(shortm, first_message + 1, std::uint64_t{10});
    shortm.erase(first_message + 9 + 10, content - 10);
    std::string cut = m.bytes;
    cut.resize(m.chunk_at[1] + 100);
    c.push_back({"MCAP cut inside a chunk",
                 {"wv", "cut.mcap"},
                 {"cut.mcap", "record at " + at(m.chunk_at[1]), "runs past the end of the file: truncated"},
                 file("cut.mcap", cut)});
    std::string big_schema =
        std::string("\x89MCAP0\r\n", 8) +
        gmwm::test::mcap_record(0x03, LeBytes().put(std::uint16_t{1}).b + std::string(17u << 20, 's'));
    c.push_back({"MCAP schema record of 17 MiB",
                 {"wv", "schema.mcap"},
                 {"schema.mcap", "record at byte 8", "a schema record of 17825794 bytes, above the limit of 16777216"},
                 file("schema.mcap", big_schema)});
    c.push_back(
        {"MCAP message shorter than its fields",
         {"wv", "m.mcap"},
         {"m.mcap", "record at " + at(first_message), "malformed message record: its log_time (8 bytes at byte 6"},
         file("m.mcap", shortm)});
  }
  // --- chunks: the stated sizes and the inflation of every codec (none, bz2, lz4, zstd) ------
  {
    const std::string zeros(std::size_t{1} << 20, '\0');  // 1 MiB: a bomb against a stated 4 kB
    const std::string bz2_bomb = gmwm::test::bz2_compress(zeros);
    const std::string lz4_bomb = gmwm::test::lz4_frame_compress(zeros);
    const std::string zstd_bomb = gmwm::test::zstd_compress(zeros);
    const std::string small(4096, 'x');
    for (const char* codec : {"bz2", "lz4"}) {
      gmwm::test::Ros1BagOptions o;
      o.compression = codec;
      const gmwm::test::Ros1Bag bag = gmwm::test::ros1_bag(o);
      std::string four_gib = bag.bytes;
      patch(four_gib, bag.chunk_size_at[0], std::uint32_t{0xffffffff});
      const std::string name = std::string("g4.") + codec + ".bag";
      c.push_back({std::string("ROS bag ") + codec + " chunk claiming 4 GiB",
                   {"wv", name},
                   {name, "chunk at " + at(bag.chunk_pos[0]),
                    "uncompressed size 4294967295 bytes, above the limit of 1073741824"},
                   file(name, four_gib)});
      std::string ratio = bag.bytes;
      patch(ratio, bag.chunk_size_at[0], std::uint32_t{(1u << 30) - 1});
      const std::string rname = std::string("r.") + codec + ".bag";
      c.push_back(
          {std::string("ROS bag ") + codec + " chunk claiming 1 GiB from a few kB",
           {"wv", rname},
           {rname, "chunk at " + at(bag.chunk_pos[0]), "more than 250 times their compressed size past 256 MiB"},
           file(rname, ratio)});
      std::string together = bag.bytes;
      for (std::uint64_t size_at : bag.chunk_size_at) patch(together, size_at, std::uint32_t{100u << 20});
      const std::string tname = std::string("t.") + codec + ".bag";
      c.push_back({std::string("ROS bag ") + codec + " chunks of 100 MiB each, past the limit together",
                   {"wv", tname},
                   {tname, "chunk at " + at(bag.chunk_pos[2]), "brings the file's chunks to 314572800 bytes"},
                   file(tname, together)});
    }
    const auto bag_bomb = [&](const char* codec, const std::string& stored) {
      const gmwm::test::Ros1Bag b = gmwm::test::ros1_bag_of_chunks({{codec, 4096, stored}});
      const std::string name = std::string("bomb.") + codec + ".bag";
      return Case{
          std::string("ROS bag ") + codec + " chunk inflating past the size it states",
          {"wv", name},
          {name, "chunk at " + at(b.chunk_pos[0]), std::string(codec) + " data does not decompress to its 4096 bytes"},
          file(name, b.bytes)};
    };
    c.push_back(bag_bomb("bz2", bz2_bomb));
    c.push_back(bag_bomb("lz4", lz4_bomb));
    const gmwm::test::Ros1Bag none = gmwm::test::ros1_bag_of_chunks({{"none", 8192, small}});
    c.push_back({"ROS bag uncompressed chunk stating another size",
                 {"wv", "none.bag"},
                 {"none.bag", "chunk at " + at(none.chunk_pos[0]),
                  "uncompressed data of 4096 bytes, its header says 8192 bytes"},
                 file("none.bag", none.bytes)});
    c.push_back({"ROS bag shorter than its first line",
                 {"wv", "short.bag"},
                 {"short.bag", "found a ROS bag of version 'r', expected 2.0"},
                 file("short.bag", "#ROSBAG Vr")});
    const gmwm::test::Ros1Bag zlib = gmwm::test::ros1_bag_of_chunks({{"zlib", 4096, small}});
    c.push_back(
        {"ROS bag chunk of an unknown compression",
         {"wv", "zlib.bag"},
         {"zlib.bag", "chunk at " + at(zlib.chunk_pos[0]), "chunk compression 'zlib', expected none, bz2 or lz4"},
         file("zlib.bag", zlib.bytes)});

    const gmwm::test::Mcap huge = gmwm::test::mcap_of_chunks({{"zstd", std::uint64_t{1} << 40, zstd_bomb}});
    c.push_back(
        {"MCAP zstd chunk claiming 1 TiB",
         {"wv", "huge.mcap"},
         {"huge.mcap", "chunk at " + at(huge.chunk_at[0]), "uncompressed size 1099511627776 bytes, above the limit"},
         file("huge.mcap", huge.bytes)});
    for (const char* codec : {"lz4", "zstd"}) {
      const gmwm::test::Mcap r = gmwm::test::mcap_of_chunks({{codec, (std::uint64_t{1} << 30) - 1, small}});
      const std::string name = std::string("r.") + codec + ".mcap";
      c.push_back({std::string("MCAP ") + codec + " chunk claiming 1 GiB from 4 kB",
                   {"wv", name},
                   {name, "chunk at " + at(r.chunk_at[0]), "more than 250 times their compressed size past 256 MiB"},
                   file(name, r.bytes)});
      const std::string& bomb = std::string(codec) == "lz4" ? lz4_bomb : zstd_bomb;
      const gmwm::test::Mcap b = gmwm::test::mcap_of_chunks({{codec, 4096, bomb}});
      const std::string bname = std::string("bomb.") + codec + ".mcap";
      c.push_back(
          {std::string("MCAP ") + codec + " chunk inflating past the size it states",
           {"wv", bname},
           {bname, "chunk at " + at(b.chunk_at[0]), std::string(codec) + " data does not decompress to its 4096 bytes"},
           file(bname, b.bytes)});
    }
    // MCAP chunks are read one after the other: two real chunks of 100 MiB of zeros (empty
    // records of 9 bytes) inflate, the third brings the file past the rule before inflating.
    c.push_back({"MCAP zstd chunks of 100 MiB each, past the limit together",
                 {"wv", "t.mcap"},
                 {"t.mcap", "chunk at byte", "brings the file's chunks to 314572788 bytes", "more than 250 times"},
                 [](const fs::path& d) {
                   constexpr std::size_t kZeros = 104857596;  // 100 MiB - 4: whole empty records
                   const std::string chunk = gmwm::test::zstd_compress(std::string(kZeros, '\0'));
                   std::vector<gmwm::test::McapStoredChunk> many(4, {"zstd", kZeros, chunk});
                   gmwm::test::write_text(d / "t.mcap", gmwm::test::mcap_of_chunks(many).bytes);
                 }});
    const gmwm::test::Mcap none_m = gmwm::test::mcap_of_chunks({{"", 8192, small}});
    c.push_back({"MCAP uncompressed chunk stating another size",
                 {"wv", "none.mcap"},
                 {"none.mcap", "chunk at " + at(none_m.chunk_at[0]),
                  "uncompressed records of 4096 bytes, its header says 8192"},
                 file("none.mcap", none_m.bytes)});
    const gmwm::test::Mcap gz = gmwm::test::mcap_of_chunks({{"gzip", 4096, small}});
    c.push_back({"MCAP chunk of an unknown compression",
                 {"wv", "gz.mcap"},
                 {"gz.mcap", "chunk at " + at(gz.chunk_at[0]), "compression 'gzip', expected '' (none), lz4 or zstd"},
                 file("gz.mcap", gz.bytes)});
  }
  // --- rosbag2: tables that are programs, values and stamps ----------------------------------
  {
    const auto bag = [](const std::string& name, gmwm::test::Rosbag2Options o) -> Setup {
      return [=](const fs::path& d) { gmwm::test::rosbag2_db((d / name).string(), o); };
    };
    const std::string recursive_messages =
        "CREATE VIEW messages(id, topic_id, timestamp, data) AS WITH RECURSIVE r(i) AS "
        "(SELECT 1 UNION ALL SELECT i + 1 FROM r) SELECT i, 1, i, zeroblob(1000) FROM r";
    const std::string recursive_topics =
        "CREATE VIEW topics(id, name, type, serialization_format) AS WITH RECURSIVE r(i) AS "
        "(SELECT 1 UNION ALL SELECT i + 1 FROM r) SELECT i, 'imu' || i, 'sensor_msgs/msg/Imu', 'cdr' FROM r";
    gmwm::test::Rosbag2Options o;
    o.messages_sql = recursive_messages;
    c.push_back({"rosbag2 messages as a recursive view",
                 {"wv", "v.db3"},
                 {"v.db3", "'messages' is a view, expected the rosbag2 table"},
                 bag("v.db3", o)});
    o.wal = true;  // and nothing may appear beside it: no -shm, no -wal
    c.push_back({"rosbag2 in WAL mode with messages as a recursive view",
                 {"wv", "w.db3"},
                 {"w.db3", "'messages' is a view"},
                 bag("w.db3", o)});
    gmwm::test::Rosbag2Options t;
    t.topics_sql = recursive_topics;
    c.push_back({"rosbag2 topics as a recursive view",
                 {"wv", "t.db3"},
                 {"t.db3", "'topics' is a view, expected the rosbag2 table"},
                 bag("t.db3", t)});
    gmwm::test::Rosbag2Options fts;
    fts.messages_sql = "CREATE VIRTUAL TABLE messages USING fts5(id, topic_id, timestamp, data)";
    c.push_back({"rosbag2 messages as a virtual table",
                 {"wv", "fts.db3"},
                 {"fts.db3", "'messages' is a virtual table, expected the rosbag2 table"},
                 bag("fts.db3", fts)});
    gmwm::test::Rosbag2Options generated;
    generated.messages_sql =
        "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL, timestamp INTEGER NOT NULL, "
        "data BLOB GENERATED ALWAYS AS (zeroblob(1000000000)) VIRTUAL)";
    c.push_back({"rosbag2 data as a generated column of 1 GB",
                 {"wv", "g.db3"},
                 {"g.db3", "column 'data' of table 'messages' is generated, expected a stored column"},
                 bag("g.db3", generated)});
    gmwm::test::Rosbag2Options nodata;
    nodata.messages_sql =
        "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER, timestamp INTEGER, blob BLOB)";
    c.push_back({"rosbag2 messages without a data column",
                 {"wv", "n.db3"},
                 {"n.db3", "table 'messages' has no column 'data', expected rosbag2's columns"},
                 bag("n.db3", nodata)});
    gmwm::test::Rosbag2Options big;
    big.messages = 2;
    big.blob = [](int) { return std::string(20u << 20, '\1'); };
    c.push_back({"rosbag2 message blob of 20 MiB",
                 {"wv", "b.db3"},
                 {"b.db3", "topic /imu message 1: cannot read it: string or blob too big"},
                 bag("b.db3", big)});
    gmwm::test::Rosbag2Options frame;
    frame.blob = [](int i) {
      std::string m = gmwm::test::imu_cdr(i, 5000000);
      if (i == 4) patch(m, 12, std::uint32_t{0xffffffff});
      return m;
    };
    c.push_back({"rosbag2 CDR frame_id of 2^32 - 1 bytes",
                 {"wv", "f.db3"},
                 {"f.db3", "topic /imu message 5: truncated: frame_id (a string of 4294967295 bytes"},
                 bag("f.db3", frame)});
    c.push_back(
        {"rosbag2 with a write-ahead log beside it",
         {"wv", "l.db3"},
         {"l.db3", "found ", "l.db3-wal beside it with changes not yet in the database", "PRAGMA wal_checkpoint"},
         [](const fs::path& d) {
           // The log of an open connection, copied beside a copy of its database.
           const fs::path live = d.parent_path() / (d.filename().string() + "-live.db3");
           sqlite3* db = nullptr;
           sqlite3_open(live.c_str(), &db);
           sqlite3_exec(db, "PRAGMA journal_mode=WAL; PRAGMA wal_autocheckpoint=0;", nullptr, nullptr, nullptr);
           sqlite3_exec(db,
                        "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT, type TEXT, serialization_format TEXT);"
                        "INSERT INTO topics VALUES (1, '/imu', 'sensor_msgs/msg/Imu', 'cdr');",
                        nullptr, nullptr, nullptr);
           fs::copy_file(live, d / "l.db3");
           fs::copy_file(live.string() + "-wal", d / "l.db3-wal");
           sqlite3_close(db);
           fs::remove(live);
         }});
  }
  return c;
}

}  // namespace

HOSTILE_CORPUS(HostileBinaryLogs, corpus());

TEST(HostileBinaryLogsCorpus, HoldsAtLeastTwentyFiveCases) { EXPECT_GE(corpus().size(), 25u); }

// The positive side of the rosbag2 cases (issue 25): a bag in WAL mode is read without any
// file appearing beside it, and a bag on read-only media (a read-only file in a read-only
// folder, read as another user when the tests run as root, whom permissions do not stop) is
// read, not refused as having "no topics table".
namespace {

std::vector<std::string> listing(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace

TEST(Rosbag2Storage, AWalModeBagIsReadAndNothingAppearsBesideIt) {
  const fs::path dir = gmwm::test::temp_dir("rosbag2_wal");
  gmwm::test::Rosbag2Options o;
  o.wal = true;
  gmwm::test::rosbag2_db((dir / "bag.db3").string(), o);
  ASSERT_EQ(listing(dir), std::vector<std::string>{"bag.db3"});
  const gmwm::test::CliRun r = gmwm::test::run_gmwm({"wv", "bag.db3", "--json", "-", "--quiet"}, dir);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(r.out)["columns"].size(), 6u);
  EXPECT_EQ(listing(dir), std::vector<std::string>{"bag.db3"});  // no bag.db3-shm, no bag.db3-wal
  fs::remove_all(dir);
}

TEST(Rosbag2Storage, ABagOnReadOnlyMediaIsRead) {
  const fs::path dir = gmwm::test::temp_dir("rosbag2_ro");
  gmwm::test::Rosbag2Options o;
  o.wal = true;  // the case that was refused: WAL without a -shm that may be created
  gmwm::test::rosbag2_db((dir / "bag.db3").string(), o);
  fs::permissions(dir / "bag.db3", fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);
  fs::permissions(dir, fs::perms::owner_read | fs::perms::owner_exec | fs::perms::group_read | fs::perms::group_exec |
                           fs::perms::others_read | fs::perms::others_exec);
  gmwm::test::RunOptions how;
  if (::geteuid() == 0) {
    how.before = "setpriv --reuid=65534 --regid=65534 --clear-groups";  // nobody
    // As nobody the program must be able to start: a build tree under a folder only its owner
    // may enter (a clone in /root, mode 0700) leaves its libraries out of nobody's reach.
    if (const gmwm::test::CliRun v = gmwm::test::run_gmwm({"--version"}, dir, how); v.exit_code != 0) {
      fs::permissions(dir, fs::perms::owner_all);
      fs::remove_all(dir);
      GTEST_SKIP() << "the program cannot start as user nobody here (" << v.err.substr(0, v.err.find('\n'))
                   << "): build in a folder others may enter to run the read-only case as root";
    }
  }
  const gmwm::test::CliRun r = gmwm::test::run_gmwm({"wv", "bag.db3", "--json", "-", "--quiet"}, dir, how);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  if (r.exit_code == 0) {
    EXPECT_EQ(nlohmann::json::parse(r.out)["columns"].size(), 6u);
  }
  EXPECT_EQ(listing(dir), std::vector<std::string>{"bag.db3"});
  fs::permissions(dir, fs::perms::owner_all);
  fs::remove_all(dir);
}
