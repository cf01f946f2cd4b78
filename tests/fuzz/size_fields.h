#pragma once
// Where the sizes, counts and offsets of a binary log are (issue 25): a walk over an input
// as far as it parses, listing each such field's byte offset and width, so that the fuzzers'
// structure-aware mutator (tools/fuzz/fuzz_main.cc) can drive exactly those fields to the
// extremes (0, 1, 2^k - 1, 2^k, 2^63, 2^64 - 1, the stated value +-1, ...) where overflow
// and over-allocation hide, instead of waiting for random bit flips to find them. Also the
// ASCII array lengths of ULog formats ("float[3]"), listed with width 0.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace gmwm::fuzz {

struct SizeField {
  std::size_t offset;
  std::size_t width;  ///< 1, 2, 4 or 8 bytes little-endian; 0: ASCII digits of a ULog array length
};

/// The size fields of a PX4 ULog (message sizes, msg_ids, format array lengths).
std::vector<SizeField> ulog_size_fields(const std::uint8_t* data, std::size_t size);
/// The size fields of a ROS 1 bag (record header and data lengths, header field lengths, the
/// values of index_pos, chunk_pos, size, count, conn_count, chunk_count), also inside
/// uncompressed chunks, and the CDR-like string lengths of the messages.
std::vector<SizeField> rosbag1_size_fields(const std::uint8_t* data, std::size_t size);
/// The size fields of an MCAP file (record lengths, string and byte-array lengths, a chunk's
/// uncompressed size and records length), also inside uncompressed chunks, and the CDR
/// frame_id length of the messages.
std::vector<SizeField> mcap_size_fields(const std::uint8_t* data, std::size_t size);
/// The size fields of a CDR sensor_msgs/msg/Imu (the frame_id length).
std::vector<SizeField> cdr_size_fields(const std::uint8_t* data, std::size_t size);

/// Sets one of `fields` (chosen by `seed`) of `data` to an extreme value (also chosen by
/// `seed`); returns false when there is none.
bool drive_to_extreme(std::uint8_t* data, std::size_t size, const std::vector<SizeField>& fields, std::uint64_t seed);

}  // namespace gmwm::fuzz
