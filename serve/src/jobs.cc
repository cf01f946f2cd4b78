#include "jobs.h"

#include <exception>
#include <random>

#include <spdlog/spdlog.h>

#include "gmwm/engine/error.h"
#include "request.h"

namespace gmwm::serve::detail {

namespace {
// A full queue's Retry-After: a fit of a 1e6-sample axis takes ~0.05 s and a selection a
// second or two, so a few seconds usually frees a place.
constexpr int kRetryAfterSeconds = 5;
}  // namespace

struct Job {
  std::string id, kind;
  Jobs::Work work;
  std::atomic<bool> cancel{false};
  // Written by the job's progress callbacks (from any of its threads), read by status().
  std::atomic<double> done{0.0}, total{0.0};
  // Guarded by the Jobs' mutex:
  std::string state = "queued";
  Json result;
  std::shared_ptr<const void> attached;
  std::string error;
  std::chrono::steady_clock::time_point polled, started, ended;
};

std::string random_id(const std::string& prefix) {
  static std::mutex m;
  static std::random_device device;
  std::lock_guard lock(m);
  static constexpr char kHex[] = "0123456789abcdef";
  std::string id = prefix + "-";
  for (int i = 0; i < 8; ++i) {
    const unsigned v = device();
    for (int k = 0; k < 4; ++k) id += kHex[(v >> (4 * k)) & 0xF];
  }
  return id;
}

void JobContext::check() const {
  if (job_ && job_->cancel.load()) throw Cancelled();
}

void JobContext::progress(double done, double total) {
  check();
  // Two atomics, not a pair: a poll between the two stores shows a fraction of the next
  // total for one poll, which the page draws as it is.
  job_->total = total;
  job_->done = done;
}

void JobContext::attach(std::shared_ptr<const void> what) { attached_ = std::move(what); }

Jobs::Jobs(int workers, double idle_seconds, std::size_t max_queued,
           std::function<std::string(const std::string&)> public_text)
    : idle_seconds_(idle_seconds), max_queued_(max_queued), public_text_(std::move(public_text)) {
  for (int i = 0; i < workers; ++i) workers_.emplace_back([this] { worker(); });
}

Jobs::~Jobs() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
    for (auto& [id, job] : jobs_) job->cancel = true;
  }
  wake_.notify_all();
  for (std::thread& t : workers_) t.join();
}

std::string Jobs::submit(const std::string& kind, Work work) {
  auto job = std::make_shared<Job>();
  job->id = random_id("j");
  job->kind = kind;
  job->work = std::move(work);
  job->polled = Clock::now();
  {
    std::lock_guard lock(mutex_);
    reap_locked(Clock::now());
    const std::size_t waiting = queued_locked();
    if (waiting >= max_queued_)
      throw HttpError(429,
                      kind + ": " + std::to_string(waiting) + " analyses are already waiting for the " +
                          std::to_string(workers_.size()) + " workers; try again once one has finished, or cancel one",
                      kRetryAfterSeconds);
    jobs_[job->id] = job;
    queue_.push_back(job);
  }
  wake_.notify_one();
  return job->id;
}

std::optional<Json> Jobs::status(const std::string& id) {
  std::lock_guard lock(mutex_);
  const auto now = Clock::now();
  reap_locked(now);
  const auto it = jobs_.find(id);
  if (it == jobs_.end()) return std::nullopt;
  Job& j = *it->second;
  j.polled = now;
  Json s = {
      {"job", j.id}, {"kind", j.kind}, {"state", j.state}, {"progress", Json::array({j.done.load(), j.total.load()})}};
  if (j.state == "done") s["result"] = j.result;
  if (j.state == "failed") s["error"] = j.error;
  if (j.state != "queued") {
    const auto end = j.state == "running" ? now : j.ended;
    s["seconds"] = std::chrono::duration<double>(end - j.started).count();
  }
  return s;
}

bool Jobs::cancel(const std::string& id) {
  std::lock_guard lock(mutex_);
  const auto it = jobs_.find(id);
  if (it == jobs_.end()) return false;
  Job& j = *it->second;
  j.cancel = true;
  if (j.state == "queued") {
    j.state = "cancelled";
    j.started = j.ended = Clock::now();
  }
  return true;
}

std::shared_ptr<const void> Jobs::attachment(const std::string& id) {
  std::lock_guard lock(mutex_);
  const auto it = jobs_.find(id);
  if (it == jobs_.end() || it->second->state != "done") return nullptr;
  it->second->polled = Clock::now();
  return it->second->attached;
}

std::size_t Jobs::queued_locked() const {
  std::size_t n = 0;
  for (const auto& j : queue_) n += j->state == "queued";
  return n;
}

std::size_t Jobs::queued() const {
  std::lock_guard lock(mutex_);
  return queued_locked();
}

std::size_t Jobs::size() const {
  std::lock_guard lock(mutex_);
  return jobs_.size();
}

void Jobs::reap_locked(Clock::time_point now) {
  for (auto it = jobs_.begin(); it != jobs_.end();) {
    Job& j = *it->second;
    const double idle = std::chrono::duration<double>(now - j.polled).count();
    if (idle <= idle_seconds_) {
      ++it;
      continue;
    }
    if (j.state == "queued" || j.state == "running") {
      // Nobody is waiting for it: stop it; it is forgotten once it has ended.
      if (!j.cancel.exchange(true)) spdlog::info("serve: job {} not polled for {:.0f} s: cancelled", j.id, idle);
      if (j.state == "queued") j.state = "cancelled";
      ++it;
      continue;
    }
    it = jobs_.erase(it);
  }
}

void Jobs::worker() {
  for (;;) {
    std::shared_ptr<Job> job;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [&] { return stopping_ || !queue_.empty(); });
      if (stopping_) return;
      job = std::move(queue_.front());
      queue_.pop_front();
      if (job->state != "queued") continue;  // cancelled while queued
      job->state = "running";
      job->started = Clock::now();
    }
    JobContext context;
    context.job_ = job.get();
    std::string state = "done", error;
    Json result;
    try {
      context.check();
      result = job->work(context);
    } catch (const Cancelled&) {
      state = "cancelled";
    } catch (const std::exception& e) {
      state = "failed";
      error = public_text_ ? public_text_(e.what()) : e.what();
    } catch (...) {
      state = "failed";
      error = "the job failed with an unknown error";
    }
    std::lock_guard lock(mutex_);
    job->state = state;
    job->result = std::move(result);
    if (state == "done") job->attached = std::move(context.attached_);
    job->error = error;
    job->ended = Clock::now();
    job->work = nullptr;  // what it captured (a dataset) is released now
  }
}

}  // namespace gmwm::serve::detail
