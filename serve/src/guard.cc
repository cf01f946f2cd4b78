#include "guard.h"

#include <algorithm>
#include <cctype>

#include "gmwm/engine/error.h"
#include "jobs.h"
#include "request.h"

namespace gmwm::serve::detail {

namespace {

// The names of this machine's loopback interface a browser may send as Host.
constexpr const char* kLoopbackNames[] = {"localhost", "127.0.0.1", "::1"};
// The wildcard addresses (listen on every interface): not a name a request can carry.
constexpr const char* kWildcardAddresses[] = {"0.0.0.0", "::", "[::]"};

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

std::string without_brackets(const std::string& host) {
  if (host.size() >= 2 && host.front() == '[' && host.back() == ']') return host.substr(1, host.size() - 2);
  return host;
}

struct Authority {
  std::string name;  ///< lower case, IPv6 without brackets
  int port = 80;     ///< HTTP's when none is named
};

// "name", "name:port", "[v6]", "[v6]:port": the parts, nullopt when malformed.
std::optional<Authority> parse_authority(const std::string& text) {
  Authority a;
  std::string rest;
  if (!text.empty() && text.front() == '[') {
    const auto close = text.find(']');
    if (close == std::string::npos) return std::nullopt;
    a.name = lower(text.substr(1, close - 1));
    rest = text.substr(close + 1);
  } else {
    const auto colon = text.find(':');
    a.name = lower(text.substr(0, colon));
    rest = colon == std::string::npos ? std::string() : text.substr(colon);
  }
  if (a.name.empty()) return std::nullopt;
  if (!rest.empty()) {
    const std::string digits = rest.substr(1);
    if (rest.front() != ':' || digits.empty() || digits.size() > 5 ||
        digits.find_first_not_of("0123456789") != std::string::npos)
      return std::nullopt;
    a.port = std::stoi(digits);
  }
  return a;
}

HttpResponse refusal(int status, const std::string& message) {
  return {status, "application/json", Json{{"error", printable_line(message)}}.dump()};
}

}  // namespace

std::string header_of(const HttpRequest& r, const std::string& lower_name) {
  const auto it = r.headers.find(lower_name);
  return it == r.headers.end() ? std::string() : it->second;
}

Guard::Guard(const ServeOptions& o) : port_(o.port) {
  for (const char* n : kLoopbackNames) names_.emplace_back(n);
  const auto wildcard = std::find(std::begin(kWildcardAddresses), std::end(kWildcardAddresses), o.host);
  if (wildcard == std::end(kWildcardAddresses)) names_.push_back(lower(without_brackets(o.host)));
  for (const std::string& h : o.allowed_hosts) names_.push_back(lower(without_brackets(h)));
}

bool Guard::names_this_server(const std::string& authority) const {
  const auto a = parse_authority(authority);
  return a && a->port == port_ && std::find(names_.begin(), names_.end(), a->name) != names_.end();
}

std::optional<HttpResponse> Guard::screen(const HttpRequest& r) const {
  const std::string where = r.method + " " + r.path;
  // 1. A request that does not name this server came through a name that is not its own
  //    (a rebound domain) or is no HTTP/1.1 request at all.
  const std::string host = header_of(r, "host");
  if (!names_this_server(host))
    return refusal(403, where + ": Host '" + host + "' is not this server (expected localhost:" +
                            std::to_string(port_) + ", 127.0.0.1:" + std::to_string(port_) +
                            " or a name given with --allow-host); a page whose domain points here is refused");
  return std::nullopt;
}

const std::vector<std::pair<std::string, std::string>>& Guard::answer_headers() {
  static const std::vector<std::pair<std::string, std::string>> headers = {
      // The page is the program's own: it never changes while the server runs, but a
      // rebuilt program must not be shadowed by a cached page.
      {"Cache-Control", "no-store"},
      {"X-Content-Type-Options", "nosniff"},
  };
  return headers;
}

HttpResponse Guard::stamped(HttpResponse a) {
  a.headers.insert(a.headers.begin(), answer_headers().begin(), answer_headers().end());
  return a;
}

}  // namespace gmwm::serve::detail
