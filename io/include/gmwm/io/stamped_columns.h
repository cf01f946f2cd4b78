#pragma once
// A delimited text file whose timestamp columns each stamp the columns to their right, the
// sensors at their own rates in one table (issue 47, item 3):
//
//   gyro_timestamp [ns],gyro_x,gyro_y,gyro_z,accel_timestamp [ns],accel_x,accel_y,accel_z
//   1700000000000000000,0.001,-0.002,0.0004,1700000000000000000,0.02,9.81,0.01
//   1700000002500000000,0.002,-0.001,0.0003,,,,
//
// A row leaves a sensor's cells empty (its stamp too) when that sensor has no sample then.
// Each stamp column's columns are read at the rate of their own stamps, the rows without a
// stamp of theirs skipped (io::read_request_parts); read together under one stamp they
// would be timed by another sensor's clock, which the reader refuses.

#include <cstddef>
#include <string>
#include <vector>

namespace gmwm::io {

struct StampedColumns {
  std::string stamp;                 ///< the timestamp column's header
  std::size_t stamp_field = 0;       ///< its place, 1-based
  std::vector<std::size_t> fields;   ///< the columns it stamps, 1-based (as --columns takes them)
  std::vector<std::string> columns;  ///< their names
};

/// The file's timestamp columns that each stamp the columns to their right (up to the next
/// timestamp column), when two or more do; empty otherwise, and for a log or bag. The header
/// and the first data row are read, nothing more. Throws InputError as reading the file would
/// for a missing, empty or headless file.
std::vector<StampedColumns> stamped_columns(const std::string& path);

}  // namespace gmwm::io
