#pragma once
// A given Allan-deviation, Allan-variance or wavelet-variance curve (`gmwm fit --curve FILE`,
// gmwm.fit_curve; engine/curve.h, docs/curve-fit.md): delimited text (comma, tab, semicolon
// or whitespace, from its header row) with a header naming its columns, lines starting with
// '#' and blank lines skipped. The columns, by name (case and a unit in brackets ignored:
// "tau [s]"), in any order, others ignored:
//
//   tau_seconds or tau      the averaging time in seconds (adev, avar) or the WV's scale (wv);
//                           tau_seconds first where both are (gmwm wv --csv's tau is samples)
//   adev|oadev, avar|oavar, wv, or value
//                           the curve's values: which quantity from --value, else from the
//                           column's name (value needs --value)
//   ci_low, ci_high         optional: each value's interval (or low, high)
//   edf                     optional: each point's equivalent degrees of freedom (or dof)
//   column                  optional: the curve a row belongs to (several in one file)
//
// so that `gmwm wv --adev-csv` (column,m,tau_seconds,adev,ci_low,ci_high,edf) and `gmwm wv
// --csv` (column,level,tau,tau_seconds,wv,ci_low,ci_high,coefficients) are read as written.
//
//   gmwm::io::CurveReadOptions o;
//   o.quantity = gmwm::CurveQuantity::kAdev;
//   const std::vector<gmwm::GivenCurve> curves = gmwm::io::read_curves("adev.csv", o);

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "gmwm/engine/curve.h"

namespace gmwm::io {

struct CurveReadOptions {
  /// What the values are (--value); nullopt: from the value column's name.
  std::optional<CurveQuantity> quantity;
  /// The curves to keep, by their `column` field (--columns); empty: every curve.
  std::vector<std::string> columns;
};

/// The most a curve file may hold: 16 MiB. A curve at every averaging factor of a 10^5-point
/// record (allantools' "all" taus) is about 5 MB as CSV; a datasheet's is a few hundred bytes.
inline constexpr std::size_t kMaxCurveBytes = std::size_t{16} << 20;

/// The curves of a file, each checked (engine curve_problem). Throws InputError, one line
/// naming "FILE:LINE:COLUMN" where it applies: an unreadable file (a folder, a device, beyond
/// kMaxCurveBytes: side_file.h), a NUL byte, no header, no tau or value column (the header
/// read listed), a value column that does not say its quantity without --value, two of them,
/// half an interval, a field that is not a finite decimal number, a row of too few fields, a
/// --columns name no row has, and everything curve_problem refuses (non-positive values,
/// taus that do not increase, a repeated tau, an interval that does not hold its value ...).
std::vector<GivenCurve> read_curves(const std::string& path, const CurveReadOptions& options);

/// A curve from named columns of numbers (Python's dict or DataFrame), read by the header
/// rules above (no `column` field: one curve); `source` names it in messages ("curve", the
/// fields as "name[k]"). Throws InputError as read_curves does.
GivenCurve curve_from_columns(const std::vector<std::string>& names, const std::vector<std::vector<double>>& columns,
                              const std::string& source, const CurveReadOptions& options);

}  // namespace gmwm::io
