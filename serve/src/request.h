#pragma once
// The app's request bodies and refusals: a JSON object read field by field, each wrong
// field named in a one-line error, and the HTTP error every handler throws.

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace gmwm::serve::detail {

using Json = nlohmann::ordered_json;

/// An answer other than 200: its status and one line for the page.
class HttpError : public std::runtime_error {
 public:
  /// `retry_after_seconds` > 0: when to try again (a 429's Retry-After header).
  HttpError(int status, const std::string& message, int retry_after_seconds = 0)
      : std::runtime_error(message), status_(status), retry_after_(retry_after_seconds) {}
  int status() const { return status_; }
  int retry_after_seconds() const { return retry_after_; }

 private:
  int status_;
  int retry_after_;
};

/// A request's JSON object. Throws HttpError 400 naming the endpoint and field.
class RequestBody {
 public:
  /// `where`: the endpoint ("/api/fit"), for messages. 413 beyond `max_bytes`.
  RequestBody(const std::string& text, const std::string& where, std::int64_t max_bytes);
  explicit RequestBody(Json object, std::string where) : j_(std::move(object)), where_(std::move(where)) {}

  bool has(const char* key) const;
  std::string text(const char* key, const std::string& fallback = {}) const;
  std::string required_text(const char* key, const std::string& expected) const;
  std::optional<double> number(const char* key) const;
  std::optional<std::int64_t> whole(const char* key, std::int64_t lo, std::int64_t hi) const;
  bool flag(const char* key, bool fallback) const;
  /// A list of strings, given as an array or as one comma-separated string.
  std::vector<std::string> list(const char* key) const;
  /// A nested object, nullopt when absent or null.
  std::optional<RequestBody> object(const char* key) const;
  const Json& json() const { return j_; }
  const std::string& where() const { return where_; }

  /// HttpError 400 "<where>: field '<key>': <what>".
  [[noreturn]] void fail(const char* key, const std::string& what) const;

 private:
  const Json* find(const char* key) const;
  Json j_;
  std::string where_;
};

}  // namespace gmwm::serve::detail
