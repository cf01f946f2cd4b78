#include "gmwm/engine/model_syntax.h"

#include <cctype>
#include <charconv>
#include <cstdio>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <utility>

#include "gmwm/engine/error.h"
#include "gmwm/engine/process_registry.h"

namespace gmwm {
namespace {

// Upper bound on "k*NAME" repeats: more latent components than this cannot be
// identified from the ~20-30 levels of any realistic series.
constexpr long kMaxRepeat = 16;
// Structural keys (ARMA's orders p and q) are small integers; beyond this a value is a
// typo, and converting it to an integer would overflow (found by fuzzing).
constexpr double kMaxStructuralValue = 1000.0;

class Parser {
 public:
  // `values`: false checks the text alone (names, structure, no value converted or checked:
  // their display units may need the rate).
  Parser(const std::string& spec, const ProcessContext& ctx, bool values = true)
      : s_(spec), ctx_(ctx), values_(values) {}

  Model parse() {
    std::vector<Component> comps;
    skip();
    if (at_end()) fail("an empty model", "a process name such as WN or 3*AR1");
    while (true) {
      parse_term(comps);
      skip();
      if (at_end()) break;
      if (s_[pos_] != '+') fail(found(), "'+' or the end of the model");
      ++pos_;
      skip();
    }
    return Model(std::move(comps));
  }

 private:
  [[noreturn]] void fail(const std::string& what, const std::string& expected) const {
    std::ostringstream os;
    os << "model '" << s_ << "', column " << (pos_ + 1) << ": found " << what << ", expected " << expected;
    throw InputError(os.str());
  }
  [[noreturn]] void fail_msg(const std::string& msg) const { throw InputError("model '" + s_ + "': " + msg); }
  std::string found() const {
    if (at_end()) return "the end of the model";
    return std::string("'") + s_[pos_] + "'";
  }
  bool at_end() const { return pos_ >= s_.size(); }
  void skip() {
    while (!at_end() && std::isspace(static_cast<unsigned char>(s_[pos_]))) ++pos_;
  }
  std::string ident() {
    const std::size_t b = pos_;
    while (!at_end() && (std::isalnum(static_cast<unsigned char>(s_[pos_])) || s_[pos_] == '_')) ++pos_;
    return s_.substr(b, pos_ - b);
  }
  double number() {
    skip();
    const char* first = s_.data() + pos_;
    const char* last = s_.data() + s_.size();
    if (first < last && *first == '+') ++first;
    double v = 0.0;
    auto [ptr, ec] = std::from_chars(first, last, v);
    if (ec != std::errc() || !std::isfinite(v)) fail(found(), "a finite number");
    pos_ = static_cast<std::size_t>(ptr - s_.data());
    return v;
  }

  void parse_term(std::vector<Component>& comps) {
    long repeat = 1;
    if (std::isdigit(static_cast<unsigned char>(s_[pos_]))) {
      const std::size_t b = pos_;
      while (!at_end() && std::isdigit(static_cast<unsigned char>(s_[pos_]))) ++pos_;
      // The count as written (shortened when absurdly long): no leading zero, at most the
      // digits kMaxRepeat has, so that no digit is silently dropped.
      const std::string digits = s_.substr(b, pos_ - b);
      const std::string shown = digits.size() > 24 ? digits.substr(0, 21) + "..." : digits;
      const std::size_t max_digits = std::to_string(kMaxRepeat).size();
      repeat = digits.size() <= max_digits ? std::stol(digits) : kMaxRepeat + 1;
      skip();
      if (at_end() || s_[pos_] != '*') fail(found(), "'*' after a repeat count");
      ++pos_;
      skip();
      if (digits.size() > 1 && digits[0] == '0') {
        pos_ = b;
        fail("repeat count '" + shown + "'", "a count without leading zeros, from 1 to " + std::to_string(kMaxRepeat));
      }
      if (repeat < 1 || repeat > kMaxRepeat) {
        pos_ = b;
        fail("repeat count " + shown, "a count from 1 to " + std::to_string(kMaxRepeat));
      }
    }
    const std::size_t name_pos = pos_;
    const std::string name = ident();
    if (name.empty()) fail(found(), "a process name such as WN, AR1 or RW");
    const ProcessEntry* entry = ProcessRegistry::instance().find(name);
    if (!entry) {
      pos_ = name_pos;
      std::string known;
      for (const auto& n : ProcessRegistry::instance().names()) known += (known.empty() ? "" : ", ") + n;
      fail_msg("unknown process '" + name + "' at column " + std::to_string(name_pos + 1) + " (known: " + known + ")");
    }
    // Arguments.
    std::vector<std::pair<std::string, double>> args;
    std::vector<std::size_t> arg_pos;
    skip();
    if (!at_end() && s_[pos_] == '(') {
      ++pos_;
      skip();
      if (!at_end() && s_[pos_] == ')') {
        ++pos_;
      } else {
        while (true) {
          skip();
          arg_pos.push_back(pos_);
          const std::string key = ident();
          if (key.empty()) fail(found(), "a parameter name such as sigma2");
          skip();
          if (at_end() || s_[pos_] != '=') fail(found(), "'=' after parameter '" + key + "'");
          ++pos_;
          args.emplace_back(key, number());
          skip();
          if (at_end()) fail(found(), "',' or ')'");
          if (s_[pos_] == ',') {
            ++pos_;
            continue;
          }
          if (s_[pos_] == ')') {
            ++pos_;
            break;
          }
          fail(found(), "',' or ')'");
        }
      }
    }
    // Structural arguments first.
    ProcessArgs pargs;
    pargs.context = ctx_;
    std::vector<std::pair<std::string, double>> values;
    for (const auto& [key, v] : args) {
      bool structural = false;
      for (const auto& sk : entry->structural_keys)
        if (sk == key) structural = true;
      if (structural) {
        if (v != std::floor(v) || !(std::abs(v) <= kMaxStructuralValue)) {
          char got[32];
          std::snprintf(got, sizeof got, "%g", v);
          fail_msg(entry->name + ": " + key + " must be an integer from 0 to " +
                   std::to_string(static_cast<long>(kMaxStructuralValue)) + " (got " + got + ")");
        }
        pargs.structural[key] = static_cast<long>(v);
      } else {
        values.emplace_back(key, v);
      }
    }
    std::shared_ptr<const Process> proc = ProcessRegistry::instance().create(entry->name, pargs);
    std::vector<double> given(static_cast<std::size_t>(proc->size()), std::numeric_limits<double>::quiet_NaN());
    for (const auto& [key, v] : values) {
      int k = -1;
      for (int i = 0; i < proc->size(); ++i)
        if (proc->parameters()[static_cast<std::size_t>(i)].name == key) k = i;
      if (k < 0) {
        std::string names;
        for (const auto& p : proc->parameters()) names += (names.empty() ? "" : ", ") + p.name;
        fail_msg(proc->name() + " has no parameter '" + key + "' (parameters: " + names + ")");
      }
      if (!std::isnan(given[static_cast<std::size_t>(k)]))
        fail_msg(proc->name() + ": parameter '" + key + "' given twice");
      given[static_cast<std::size_t>(k)] = values_ ? proc->from_display(k, v) : v;
    }
    if (!values_) {
      for (long r = 0; r < repeat; ++r) comps.push_back(Component{proc, given});
      return;
    }
    // Check the given values one by one (a negative variance, |phi| >= 1, ...).
    {
      std::vector<double> probe(given);
      const auto guess_ok = [&](std::size_t i) { return !std::isnan(probe[i]); };
      bool all = true;
      for (std::size_t i = 0; i < probe.size(); ++i) all = all && guess_ok(i);
      if (all) {
        const std::string why = proc->validate(probe);
        if (!why.empty()) fail_msg(proc->name() + ": " + why);
      } else {
        for (std::size_t i = 0; i < probe.size(); ++i) {
          if (!guess_ok(i)) continue;
          std::vector<double> one(probe.size());
          // Fill the other slots with a value valid for their transform.
          for (std::size_t k = 0; k < one.size(); ++k) {
            switch (proc->parameters()[k].transform) {
              case Transform::kLog:
                one[k] = 1.0;
                break;
              case Transform::kAtanh:
                one[k] = 0.0;
                break;
              case Transform::kIdentity:
                one[k] = 0.0;
                break;
              case Transform::kLogitHalf:
                one[k] = 0.25;
                break;
            }
          }
          one[i] = probe[i];
          const std::string why = proc->validate(one);
          if (!why.empty()) fail_msg(proc->name() + ": " + why);
        }
      }
    }
    for (long r = 0; r < repeat; ++r) comps.push_back(Component{proc, given});
  }

  const std::string& s_;
  ProcessContext ctx_;
  bool values_ = true;
  std::size_t pos_ = 0;
};

// At most one each of the linear and deterministic processes (WN, QN, RW, DR).
void check_identifiable(const Model& model, const std::string& spec) {
  std::map<std::string, int> count;
  for (const auto& c : model.components()) {
    const Process& p = *c.process;
    if (p.linear() || p.deterministic()) {
      if (++count[p.name()] > 1)
        throw InputError("model '" + spec + "': " + p.name() + " appears more than once; sums of " + p.name() +
                         " processes are not identifiable from a wavelet variance (use one)");
    }
  }
}

}  // namespace

Model parse_model(const std::string& spec, const ProcessContext& context) {
  Model model = Parser(spec, context).parse();
  check_identifiable(model, spec);
  return model;
}

ModelSpec::ModelSpec(std::string text) : text_(std::move(text)) {
  if (!text_.empty()) check_identifiable(Parser(text_, ProcessContext{}, false).parse(), text_);
}

ModelSpec::ModelSpec(const char* text) : ModelSpec(std::string(text)) {}

Model ModelSpec::bind(const ProcessContext& context) const { return parse_model(text_, context); }

void check_model_fits_levels(const Model& model, int levels) {
  if (model.num_parameters() > levels)
    throw InputError("model '" + model.to_string() + "' has " + std::to_string(model.num_parameters()) +
                     " parameters but the wavelet "
                     "variance has only " +
                     std::to_string(levels) + " levels: use a smaller model or a longer series");
}

}  // namespace gmwm
