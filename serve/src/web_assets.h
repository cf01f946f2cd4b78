#pragma once
// The web app's files (serve/web/), embedded into the library at build time
// (cmake/embed_web_assets.cmake writes web_assets.cc), so that the program needs no
// installed data files and serves exactly the page it was built with.

#include <string_view>

namespace gmwm::serve::detail {

/// The content of serve/web/<name> ("index.html", "app.js", "app.css"); empty when absent.
std::string_view web_asset(std::string_view name);

}  // namespace gmwm::serve::detail
