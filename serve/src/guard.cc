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

// The page's own files: nothing in them is the user's, so they load without the token (the
// page that asks for it has no other way to show).
constexpr const char* kPublicFiles[] = {"/app.js", "/app.css", "/vega.js", "/favicon.ico"};
// The page itself, where the start-up address's ?token= is exchanged for the cookie.
bool is_page(const std::string& path) { return path == "/" || path == "/index.html"; }

// The methods the app answers.
constexpr const char* kMethods[] = {"GET", "HEAD", "POST", "DELETE"};

// What a browser's Sec-Fetch-Site says of a request the page itself made (or one the user
// typed): anything else (same-site: another port of localhost; cross-site) came from
// another page.
constexpr const char* kOwnFetchSites[] = {"same-origin", "none"};

// The media type of a Content-Type (before its parameters), lower case, trimmed.
std::string media_type(const std::string& content_type) {
  std::string t = lower(content_type.substr(0, content_type.find(';')));
  const auto a = t.find_first_not_of(" \t"), b = t.find_last_not_of(" \t");
  return a == std::string::npos ? std::string() : t.substr(a, b - a + 1);
}

// The value of cookie `name` in a Cookie header ("a=1; b=2"); nullopt when absent.
std::optional<std::string> cookie_value(const std::string& cookies, const std::string& name) {
  std::size_t start = 0;
  while (start < cookies.size()) {
    std::size_t end = cookies.find(';', start);
    if (end == std::string::npos) end = cookies.size();
    std::string pair = cookies.substr(start, end - start);
    const auto a = pair.find_first_not_of(' ');
    pair = a == std::string::npos ? std::string() : pair.substr(a);
    if (pair.size() > name.size() && pair.compare(0, name.size(), name) == 0 && pair[name.size()] == '=')
      return pair.substr(name.size() + 1);
    start = end + 1;
  }
  return std::nullopt;
}

// The page a browser shows for / without the token: what to open instead.
HttpResponse token_page(int port) {
  const std::string html =
      "<!doctype html><html lang=\"en\"><head><meta charset=\"utf-8\"><title>gmwm serve</title></head><body>"
      "<h1>gmwm serve</h1><p>This page needs the address <code>gmwm serve</code> printed when it started: "
      "<code>http://127.0.0.1:" +
      std::to_string(port) +
      "/?token=&hellip;</code> (the token keeps other pages and other users of this machine out). Open that "
      "address, or start <code>gmwm serve</code> again.</p></body></html>";
  return {401, "text/html; charset=utf-8", html};
}

}  // namespace

std::string header_of(const HttpRequest& r, const std::string& lower_name) {
  const auto it = r.headers.find(lower_name);
  return it == r.headers.end() ? std::string() : it->second;
}

bool same_secret(const std::string& a, const std::string& b) {
  if (a.size() != b.size()) return false;
  unsigned char diff = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    diff = static_cast<unsigned char>(diff | (static_cast<unsigned char>(a[i]) ^ static_cast<unsigned char>(b[i])));
  return diff == 0;
}

std::string random_token() {
  std::string t = random_id("t").substr(2);
  return t.substr(0, kTokenHexDigits);
}

Guard::Guard(const ServeOptions& o) : token_(o.token.empty() ? random_token() : o.token), port_(o.port) {
  for (const char* n : kLoopbackNames) names_.emplace_back(n);
  const auto wildcard = std::find(std::begin(kWildcardAddresses), std::end(kWildcardAddresses), o.host);
  if (wildcard == std::end(kWildcardAddresses)) names_.push_back(lower(without_brackets(o.host)));
  for (const std::string& h : o.allowed_hosts) names_.push_back(lower(without_brackets(h)));
}

bool Guard::names_this_server(const std::string& authority) const {
  const auto a = parse_authority(authority);
  return a && a->port == port_ && std::find(names_.begin(), names_.end(), a->name) != names_.end();
}

std::string Guard::cookie_name() const { return "gmwm_serve_" + std::to_string(port_); }

bool Guard::carries_token(const HttpRequest& r) const {
  if (const std::string h = header_of(r, lower(kTokenHeader)); !h.empty()) return same_secret(h, token_);
  if (const std::string a = header_of(r, "authorization"); a.rfind("Bearer ", 0) == 0)
    return same_secret(a.substr(7), token_);
  const auto c = cookie_value(header_of(r, "cookie"), cookie_name());
  return c && same_secret(*c, token_);
}

std::optional<HttpResponse> Guard::screen_origin(const HttpRequest& r, const std::string& where) const {
  // 2. Browsers send Origin with every cross-origin request and every POST: only this
  //    server's own is taken ("null": a sandboxed frame, a file, a redirect chain).
  if (r.headers.count("origin")) {
    const std::string origin = header_of(r, "origin");
    constexpr std::string_view scheme = "http://";
    const bool own = origin.rfind(scheme, 0) == 0 && names_this_server(origin.substr(scheme.size()));
    if (!own)
      return refusal(403, where + ": a request from the page at '" + origin +
                              "' is refused (only this server's own page may send requests here)");
  }
  // 3. Another port of localhost is the same site as the app, but not the same origin.
  if (r.path.rfind("/api/", 0) == 0 && r.headers.count("sec-fetch-site")) {
    const std::string site = lower(header_of(r, "sec-fetch-site"));
    if (std::find(std::begin(kOwnFetchSites), std::end(kOwnFetchSites), site) == std::end(kOwnFetchSites))
      return refusal(403, where + ": a request another page made (Sec-Fetch-Site: " + site +
                              ") is refused (only this server's own page may send requests here)");
  }
  return std::nullopt;
}

std::optional<HttpResponse> Guard::screen_token(const HttpRequest& r, const std::string& where) const {
  const bool read = r.method == "GET" || r.method == "HEAD";
  if (read && std::find(std::begin(kPublicFiles), std::end(kPublicFiles), r.path) != std::end(kPublicFiles))
    return std::nullopt;
  if (read && is_page(r.path)) {
    // The start-up address: the token moves to a cookie and out of the address bar.
    const auto q = r.query.find("token");
    if (q != r.query.end() && same_secret(q->second, token_)) {
      HttpResponse to_page{303, "text/plain; charset=utf-8", "see /"};
      to_page.headers = {{"Location", "/"},
                         {"Set-Cookie", cookie_name() + "=" + token_ + "; Path=/; HttpOnly; SameSite=Strict"}};
      return to_page;
    }
    if (carries_token(r)) return std::nullopt;
    return token_page(port_);
  }
  if (carries_token(r)) return std::nullopt;
  return refusal(401, where +
                          ": this server needs its access token (the ?token= of the address it printed at start, "
                          "or an X-Gmwm-Token header)");
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
  if (auto refused = screen_origin(r, where)) return refused;
  // Only what the app answers; only a POST has a body (cpp-httplib would read one of a PUT,
  // PATCH or DELETE whole into memory).
  if (std::find(std::begin(kMethods), std::end(kMethods), r.method) == std::end(kMethods))
    return refusal(405, where + ": not allowed here (the app answers GET, POST and DELETE)");
  const std::string length = header_of(r, "content-length");
  if (r.method != "POST" && ((!length.empty() && length != "0") || r.headers.count("transfer-encoding")))
    return refusal(400, where + ": a " + r.method + " request has no body here");
  // A compressed body would be expanded beyond every limit before it is counted; only
  // chunks are a transfer encoding cpp-httplib reads as one (it would read any other to
  // the connection's end).
  if (const std::string e = lower(header_of(r, "content-encoding")); !e.empty() && e != "identity")
    return refusal(415, where + ": Content-Encoding '" + e + "' is refused, expected an uncompressed body");
  if (const std::string t = lower(header_of(r, "transfer-encoding")); !t.empty() && t != "chunked")
    return refusal(400, where + ": Transfer-Encoding '" + t + "' is refused, expected chunked or a Content-Length");
  if (auto refused = screen_token(r, where)) return refused;
  // 5. A page elsewhere can post a form (text/plain, url-encoded, multipart) without the
  //    browser asking this server first; the app's own requests name their JSON or bytes.
  if (r.method == "POST") {
    const bool upload = r.path == "/api/upload";
    const std::string expected = upload ? "application/octet-stream" : "application/json";
    const std::string found = media_type(header_of(r, "content-type"));
    if (found != expected)
      return refusal(415, where + ": Content-Type '" + (found.empty() ? std::string("none") : found) +
                              "' is refused, expected " + expected);
  }
  return std::nullopt;
}

const std::vector<std::pair<std::string, std::string>>& Guard::answer_headers() {
  static const std::vector<std::pair<std::string, std::string>> headers = {
      // The page is the program's own: it never changes while the server runs, but a
      // rebuilt program must not be shadowed by a cached page.
      {"Cache-Control", "no-store"},
      {"X-Content-Type-Options", "nosniff"},
      // What the page may load and run: its own scripts (Vega compiles its expressions with
      // Function, hence 'unsafe-eval'; no inline script), its own and inline styles (the
      // report's style sheet, Vega's element styles), its requests to this server alone,
      // images drawn in the page; no frame may hold it, no form may post elsewhere.
      {"Content-Security-Policy",
       "default-src 'none'; script-src 'self' 'unsafe-eval'; style-src 'self' 'unsafe-inline'; "
       "img-src 'self' data: blob:; connect-src 'self'; font-src 'self'; base-uri 'none'; form-action 'self'; "
       "frame-ancestors 'none'"},
      {"X-Frame-Options", "DENY"},
      {"Referrer-Policy", "no-referrer"},
      // No other origin may load an answer as an image, a script or a style either.
      {"Cross-Origin-Resource-Policy", "same-origin"},
      {"Cross-Origin-Opener-Policy", "same-origin"},
  };
  return headers;
}

HttpResponse Guard::stamped(HttpResponse a) {
  a.headers.insert(a.headers.begin(), answer_headers().begin(), answer_headers().end());
  return a;
}

}  // namespace gmwm::serve::detail
