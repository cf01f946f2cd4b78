#pragma once
// The model syntax users already know from GMWM:
//   3*AR1()+WN()+RW()+QN()+DR()          parentheses optional: 3*AR1+WN+RW
//   WN(sigma2=0.5)+AR1(phi=0.9,sigma2=1e-4)   starting values / simulation values
//   ARMA(p=2,q=1,phi1=0.5)               structural arguments, then values
// Names are case-insensitive; values are in display units (SIN's f in Hz when the
// sampling rate is known). Errors are InputError naming the model string, the column
// and what was expected.

#include <string>

#include "gmwm/engine/model.h"
#include "gmwm/engine/process.h"

namespace gmwm {

/// Parses a model string. Checks identifiability (at most one each of WN, QN, RW, DR:
/// sums of them are not identifiable from a WV) and the given values (e.g. a negative
/// variance). Does not check p <= J (that needs the data; see check_model_fits_levels).
Model parse_model(const std::string& spec, const ProcessContext& context = {});

/// Throws InputError when the model has more parameters than the WV has levels.
void check_model_fits_levels(const Model& model, int levels);

}  // namespace gmwm
