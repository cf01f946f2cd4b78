#pragma once
// The rules every request to the app passes before it is routed (docs/serve.md, "Threat
// model"), in one place: the App applies them to every request it handles and the Server
// to every request's headers before a byte of its body is read.
//
// The threat: gmwm serve runs on the user's machine while the user browses the web. A
// hostile page can make the browser send requests to 127.0.0.1 (forms, fetch, images), can
// make its own domain resolve to 127.0.0.1 (DNS rebinding: its scripts are then
// same-origin with the app), and another local user can connect to the port. Hence, in
// this order:
//   1. Host: the request must name this server, a loopback name (localhost, 127.0.0.1,
//      [::1]), the --host address or an --allow-host name, with the port it listens on
//      (403 otherwise: a rebound domain names itself).
//   2. Origin: when sent (browsers send it with every cross-origin request and every
//      POST), it must be this server's own origin (403 otherwise).
//   3. Sec-Fetch-Site: when sent to the API, it must be same-origin or none (403
//      otherwise: another port of localhost is "same-site", not same-origin).
//   4. The access token, a secret of this launch (printed in the start-up address, as
//      notebook servers do): in a cookie set when the page is opened with ?token=, or in
//      an X-Gmwm-Token or "Authorization: Bearer" header (scripts); every request but the
//      page's static files needs it (401 otherwise).
//   5. State-changing requests: POST with Content-Type application/json (the JSON
//      endpoints) or application/octet-stream (uploads), DELETE; a request a page can send
//      without the browser asking first (a form's text/plain, url-encoded or multipart) is
//      refused (415), and so is any Content-Encoding (a compressed body could expand
//      beyond every limit).

#include <optional>
#include <string>
#include <vector>

#include "gmwm/serve/app.h"

namespace gmwm::serve::detail {

/// The header a script sends the token in (the page's requests carry the cookie).
inline constexpr const char* kTokenHeader = "X-Gmwm-Token";
/// The token's length when the app draws it: 32 hex digits, 128 random bits.
inline constexpr std::size_t kTokenHexDigits = 32;

class Guard {
 public:
  /// The token is the options' one, or a fresh random one.
  explicit Guard(const ServeOptions& options);

  /// The port the server listens on (the Host and Origin must name it); the options' port
  /// until the server has bound one.
  void set_port(int port) { port_ = port; }
  int port() const { return port_; }
  const std::string& token() const { return token_; }
  /// The cookie that carries the token, one per port (cookies do not tell ports apart, and
  /// two servers on one machine must not overwrite each other's).
  std::string cookie_name() const;

  /// The answer to give instead of routing `r`: a refusal (403, 401, 415) or, for
  /// GET /?token=TOKEN, the redirect to / that keeps the token in a cookie; nullopt when
  /// the request may go on.
  std::optional<HttpResponse> screen(const HttpRequest& r) const;

  /// The headers every answer carries: no caching, no sniffing, no framing, the page's
  /// content-security policy, no referrer, resources not readable by other origins.
  static const std::vector<std::pair<std::string, std::string>>& answer_headers();
  /// `a` with answer_headers() first.
  static HttpResponse stamped(HttpResponse a);

 private:
  bool names_this_server(const std::string& authority) const;
  std::optional<HttpResponse> screen_origin(const HttpRequest& r, const std::string& where) const;
  std::optional<HttpResponse> screen_token(const HttpRequest& r, const std::string& where) const;
  bool carries_token(const HttpRequest& r) const;

  std::string token_;
  std::vector<std::string> names_;  ///< lower case, IPv6 without brackets
  int port_ = 0;
};

/// A header of `r` by its lower-case name; empty when absent.
std::string header_of(const HttpRequest& r, const std::string& lower_name);

/// True when `a` and `b` are equal, in a time that does not tell where they differ.
bool same_secret(const std::string& a, const std::string& b);

/// A fresh token: kTokenHexDigits hex digits from the system's entropy.
std::string random_token();

}  // namespace gmwm::serve::detail
