#pragma once
// The app's jobs: long work (a WV, a fit, a selection) run on a few worker threads while
// the page polls. A job reports progress through its context, which is also where it is
// cancelled (the library's progress callbacks call JobContext::progress, which throws
// gmwm::Cancelled once the job is cancelled). A job nobody polled for `idle_seconds` is
// cancelled and forgotten; a finished one is forgotten after the same time.

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

namespace gmwm::serve::detail {

using Json = nlohmann::ordered_json;

/// A random identifier ("<prefix>-" and 32 hex digits from the system's entropy): nobody
/// can guess another tab's dataset or job.
std::string random_id(const std::string& prefix);

class JobContext {
 public:
  /// Work done out of total; throws gmwm::Cancelled once the job was cancelled.
  void progress(double done, double total);
  /// Throws gmwm::Cancelled once the job was cancelled (between stages).
  void check() const;
  /// Keeps `what` with the job's result, for later requests about it (a selection's study,
  /// to render any of its ranked models: Jobs::attachment).
  void attach(std::shared_ptr<const void> what);

 private:
  friend class Jobs;
  struct Job* job_ = nullptr;
  std::shared_ptr<const void> attached_;
};

class Jobs {
 public:
  using Work = std::function<Json(JobContext&)>;

  /// `public_text`: what a failed job's message becomes before anyone reads it (no path of
  /// the machine).
  Jobs(int workers, double idle_seconds, std::size_t max_queued,
       std::function<std::string(const std::string&)> public_text);
  /// Cancels every job and waits for the workers.
  ~Jobs();
  Jobs(const Jobs&) = delete;
  Jobs& operator=(const Jobs&) = delete;

  /// Queues `work`; its id. HttpError 429 (with a Retry-After) when `max_queued` jobs are
  /// already waiting for a worker.
  std::string submit(const std::string& kind, Work work);
  /// Jobs waiting for a worker.
  std::size_t queued() const;
  /// {"job", "kind", "state": queued|running|done|failed|cancelled, "progress": [done, total],
  /// "result" | "error", "seconds"}; nullopt for an unknown (or forgotten) id. Counts as a poll.
  std::optional<Json> status(const std::string& id);
  /// Cancels a queued or running job (a finished one stays as it is); false when unknown.
  bool cancel(const std::string& id);
  /// What a finished job attached (JobContext::attach); nullptr when unknown, not done or
  /// nothing was attached. Counts as a poll.
  std::shared_ptr<const void> attachment(const std::string& id);
  /// Jobs known (queued, running or finished and not yet forgotten).
  std::size_t size() const;

 private:
  using Clock = std::chrono::steady_clock;
  void worker();
  void reap_locked(Clock::time_point now);
  std::size_t queued_locked() const;

  double idle_seconds_;
  std::size_t max_queued_;
  std::function<std::string(const std::string&)> public_text_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  bool stopping_ = false;
  std::map<std::string, std::shared_ptr<struct Job>> jobs_;
  std::deque<std::shared_ptr<struct Job>> queue_;
  std::vector<std::thread> workers_;
};

}  // namespace gmwm::serve::detail
