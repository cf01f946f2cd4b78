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

/// A model as written, checked for everything that does not need the data's sampling rate:
/// the syntax, process names, repeat counts, structural arguments, parameter names (none
/// given twice) and identifiability. What the studies take (pipeline/*_study.h): a caller
/// parses the user's text once, before any data is read, and the study binds it at the
/// data's rate (values in display units, SIN's f in Hz, are converted and checked then).
///
///   ModelSpec m("2*AR1+WN+RW");          // InputError here for "2*AR1+FOO"
///   Model model = m.bind({100.0, true});  // at 100 Hz
///
/// Converts implicitly from the text, so `options.model = "AR1+WN+RW"` parses it.
class ModelSpec {
 public:
  ModelSpec() = default;
  /// Parses and checks `text`; throws InputError (as parse_model's) when it is not a model.
  /// An empty text is an empty spec (no model given; bind() refuses it).
  ModelSpec(std::string text);  // NOLINT(google-explicit-constructor): a model is written as text
  ModelSpec(const char* text);  // NOLINT(google-explicit-constructor)
  /// The text as the user wrote it (what documents call "model_spec").
  const std::string& text() const { return text_; }
  bool empty() const { return text_.empty(); }
  /// The model at `context`'s rate: parse_model(text(), context), which also checks the given values.
  Model bind(const ProcessContext& context) const;

 private:
  std::string text_;
};

/// Throws InputError when the model has more parameters than the WV has levels.
void check_model_fits_levels(const Model& model, int levels);

}  // namespace gmwm
