#include "request.h"

#include <cmath>
#include <utility>

#include "gmwm/engine/error.h"

namespace gmwm::serve::detail {

RequestBody::RequestBody(const std::string& text, const std::string& where, std::int64_t max_bytes) : where_(where) {
  if (static_cast<std::int64_t>(text.size()) > max_bytes)
    throw HttpError(413, where + ": the request body has " + std::to_string(text.size()) + " bytes, expected at most " +
                             std::to_string(max_bytes));
  try {
    j_ = Json::parse(text);
  } catch (const Json::parse_error& e) {
    // nlohmann's message names the byte: "parse error at line 1, column 9: ...".
    std::string what = e.what();
    if (const auto p = what.find("parse error"); p != std::string::npos) what = what.substr(p);
    throw HttpError(400, printable_line(where + ": the request body is not JSON: " + what));
  } catch (const Json::exception& e) {
    // A number beyond a double (1e999) is nlohmann's out_of_range: the client's error too.
    std::string what = e.what();
    if (const auto p = what.find("] "); p != std::string::npos) what = what.substr(p + 2);
    throw HttpError(
        400, printable_line(where + ": the request body holds a value beyond what a double can hold (" + what + ")"));
  }
  if (!j_.is_object()) throw HttpError(400, where + ": expected a JSON object as the request body");
}

const Json* RequestBody::find(const char* key) const {
  const auto it = j_.find(key);
  if (it == j_.end() || it->is_null()) return nullptr;
  return &*it;
}

bool RequestBody::has(const char* key) const { return find(key) != nullptr; }

void RequestBody::fail(const char* key, const std::string& what) const {
  throw HttpError(400, printable_line(where_ + ": field '" + key + "': " + what));
}

std::string RequestBody::text(const char* key, const std::string& fallback) const {
  const Json* v = find(key);
  if (!v) return fallback;
  if (!v->is_string()) fail(key, "expected a string");
  return v->get<std::string>();
}

std::string RequestBody::required_text(const char* key, const std::string& expected) const {
  const std::string s = text(key);
  if (s.empty()) fail(key, "missing, expected " + expected);
  return s;
}

std::optional<double> RequestBody::number(const char* key) const {
  const Json* v = find(key);
  if (!v) return std::nullopt;
  if (!v->is_number()) fail(key, "expected a number");
  const double x = v->get<double>();
  if (!std::isfinite(x)) fail(key, "expected a finite number");
  return x;
}

std::optional<std::int64_t> RequestBody::whole(const char* key, std::int64_t lo, std::int64_t hi) const {
  const Json* v = find(key);
  if (!v) return std::nullopt;
  if (!v->is_number_integer())
    fail(key, "expected a whole number from " + std::to_string(lo) + " to " + std::to_string(hi));
  const std::int64_t x = v->is_number_unsigned() && v->get<std::uint64_t>() > static_cast<std::uint64_t>(hi)
                             ? hi + 1
                             : v->get<std::int64_t>();
  if (x < lo || x > hi)
    fail(key,
         "found " + v->dump() + ", expected a whole number from " + std::to_string(lo) + " to " + std::to_string(hi));
  return x;
}

bool RequestBody::flag(const char* key, bool fallback) const {
  const Json* v = find(key);
  if (!v) return fallback;
  if (!v->is_boolean()) fail(key, "expected true or false");
  return v->get<bool>();
}

std::vector<std::string> RequestBody::list(const char* key) const {
  const Json* v = find(key);
  std::vector<std::string> out;
  if (!v) return out;
  if (v->is_string()) {
    const std::string s = v->get<std::string>();
    std::size_t start = 0;
    while (start <= s.size()) {
      const std::size_t end = std::min(s.find(',', start), s.size());
      std::string item = s.substr(start, end - start);
      const auto a = item.find_first_not_of(" \t"), b = item.find_last_not_of(" \t");
      item = a == std::string::npos ? std::string() : item.substr(a, b - a + 1);
      if (item.empty()) fail(key, "found an empty entry in '" + s + "', expected names separated by commas");
      out.push_back(item);
      start = end + 1;
    }
    return out;
  }
  if (!v->is_array()) fail(key, "expected a list of strings");
  for (const Json& e : *v) {
    if (!e.is_string() || e.get<std::string>().empty()) fail(key, "expected a list of non-empty strings");
    out.push_back(e.get<std::string>());
  }
  return out;
}

std::optional<RequestBody> RequestBody::object(const char* key) const {
  const Json* v = find(key);
  if (!v) return std::nullopt;
  if (!v->is_object()) fail(key, "expected an object");
  return RequestBody(*v, where_ + " " + key);
}

}  // namespace gmwm::serve::detail
