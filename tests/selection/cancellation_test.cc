// Every long study stops at its progress callback (issue 25): a callback that throws
// gmwm::Cancelled ends the robust WV, a fit with a bootstrap Omega, a selection (its flow
// graph of fits and its bootstrap draws), a gap diagnosis (its reference and its
// attribution) and a joint fit's test at once, the exception reaching the caller through
// the parallel loops; the library then runs the same study to its end as before.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "gmwm/engine/error.h"
#include "gmwm/engine/model_syntax.h"
#include "gmwm/engine/simulate.h"
#include "gmwm/pipeline/fit_study.h"
#include "gmwm/pipeline/gap_study.h"
#include "gmwm/pipeline/replicate_study.h"
#include "gmwm/pipeline/select_study.h"
#include "gmwm/pipeline/wv_study.h"

namespace gmwm::pipeline {
namespace {

constexpr std::int64_t kN = 1 << 15;
// After the cancelling call, the study must be gone within this long (each task in flight
// finishes its current unit of work: a fit or a draw of 2^15 samples, milliseconds).
constexpr double kUnwindSeconds = 2.0;

const char* kTruth = "AR1(phi=0.99,sigma2=1e-4)+WN(sigma2=1e-2)+RW(gamma2=1e-8)";

io::SignalSet signal_set(int columns = 1) {
  const Model m = parse_model(kTruth);
  io::SignalSet set;
  set.path = "<array>";
  set.freq = 100.0;
  set.freq_known = true;
  for (int k = 0; k < columns; ++k)
    set.signals.push_back(
        {"gyro_x" + std::to_string(k), simulate(m, m.given_values(), kN, 7, static_cast<std::uint64_t>(k)), ""});
  return set;
}

// A progress callback that throws gmwm::Cancelled from its `at`-th call on (from any
// thread), and remembers when it first did.
struct Canceller {
  struct State {
    std::atomic<int> calls{0};
    int at = 1;
    std::atomic<bool> thrown{false};
    std::chrono::steady_clock::time_point when;
  };
  std::shared_ptr<State> state = std::make_shared<State>();
  explicit Canceller(int at) { state->at = at; }
  std::function<void(int, int)> callback() const {
    return [s = state](int, int) {
      if (++s->calls < s->at) return;
      if (!s->thrown.exchange(true)) s->when = std::chrono::steady_clock::now();
      throw Cancelled();
    };
  }
  int calls() const { return state->calls.load(); }
  double seconds_since_cancel() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - state->when).count();
  }
};

// Runs `study` with a canceller at call `at`: it must throw Cancelled within kUnwindSeconds.
template <class Study>
void expect_cancelled(int at, Study&& study) {
  Canceller c(at);
  EXPECT_THROW(study(c.callback()), Cancelled);
  EXPECT_GE(c.calls(), at);
  EXPECT_LT(c.seconds_since_cancel(), kUnwindSeconds);
}

TEST(Cancellation, StopsTheRobustWv) {
  const io::SignalSet set = signal_set(2);
  WvStudyOptions o;
  o.robust.emplace();
  expect_cancelled(3, [&](const std::function<void(int, int)>& p) {
    WvStudyOptions oc = o;
    oc.robust->progress = p;
    study_wv(set, oc);
  });
  EXPECT_EQ(study_wv(set, o).columns.size(), 2u);  // and it still runs to its end
}

TEST(Cancellation, StopsAFitDuringItsBootstrapOmega) {
  const io::SignalSet set = signal_set();
  FitStudyOptions o;
  o.model = "AR1+WN+RW";
  o.fit.omega = OmegaKind::kBootstrap;
  o.fit.bootstrap_replicates = 400;
  expect_cancelled(20, [&](const std::function<void(int, int)>& p) {
    FitStudyOptions oc = o;
    oc.fit.progress = p;
    study_fit(set, oc);
  });
}

TEST(Cancellation, StopsASelectionInItsFlowGraphOfFits) {
  const io::SignalSet set = signal_set(2);
  SelectStudyOptions o;
  o.models = {"2*AR1+WN+RW+QN"};
  expect_cancelled(3, [&](const std::function<void(int, int)>& p) {
    SelectStudyOptions oc = o;
    oc.select.progress = p;
    study_select(set, oc);
  });
  EXPECT_EQ(study_select(set, o).columns.size(), 2u);
}

TEST(Cancellation, StopsASelectionInItsBootstrapDraws) {
  const io::SignalSet set = signal_set();
  SelectStudyOptions o;
  o.models = {"AR1+WN+RW"};
  o.select.optimism = selection::OptimismMethod::kBootstrap;
  o.select.bootstrap_replicates = 200;
  // AR1+WN+RW has 7 sub-models: the 8th call is the first bootstrap draw's.
  expect_cancelled(40, [&](const std::function<void(int, int)>& p) {
    SelectStudyOptions oc = o;
    oc.select.progress = p;
    study_select(set, oc);
  });
}

TEST(Cancellation, StopsAGapDiagnosisInItsReferenceAndItsAttribution) {
  io::SignalSet set = signal_set();
  GapStudyOptions o;
  o.baseline = ModelBaseline{"WN(sigma2=1e-2)+RW(gamma2=1e-8)"};
  o.gap.replicates = 100;
  for (int at : {10, 100 + 20}) {  // a reference replicate, then a fit of the attribution
    expect_cancelled(at, [&](const std::function<void(int, int)>& p) {
      GapStudyOptions oc = o;
      oc.progress = [p](double, double) { p(0, 0); };
      study_gap(set, oc);
    });
  }
}

TEST(Cancellation, StopsAJointFitInItsTest) {
  const Model m = parse_model(kTruth);
  ReplicateGroup g;
  g.axis = "gyro_x";
  for (std::uint64_t k = 0; k < 3; ++k) {
    g.sources.push_back("r" + std::to_string(k) + ".csv:gyro_x");
    g.series.emplace_back(simulate(m, m.given_values(), kN, 11, k));
  }
  JointFitStudyOptions o;
  o.model = "AR1+WN+RW";
  o.test_draws = 200;
  expect_cancelled(10, [&](const std::function<void(int, int)>& p) {
    JointFitStudyOptions oc = o;
    oc.progress = p;
    study_joint_fit({g}, ProcessContext{100.0, true}, oc);
  });
}

}  // namespace
}  // namespace gmwm::pipeline
