#pragma once
// Loading a page in headless Chromium (Debian's `chromium`) for the report tests: the DOM after the page's
// scripts ran, a screenshot, and Chromium's log (console messages appear there as "CONSOLE" lines).
// Each load uses a new empty profile and no network services.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>

#include <unistd.h>

namespace glmbslam::test {

/// The Chromium executable on PATH (chromium, chromium-browser, google-chrome), or nothing.
inline std::optional<std::filesystem::path> find_chromium() {
  const char* path = std::getenv("PATH");
  if (path == nullptr) return std::nullopt;
  for (const char* name : {"chromium", "chromium-browser", "google-chrome"}) {
    std::stringstream dirs(path);
    std::string dir;
    while (std::getline(dirs, dir, ':')) {
      const std::filesystem::path candidate = std::filesystem::path(dir) / name;
      if (!dir.empty() && ::access(candidate.c_str(), X_OK) == 0) return candidate;
    }
  }
  return std::nullopt;
}

struct BrowserLoad {
  int exit_code = -1;
  std::string dom;                   ///< serialised DOM after the scripts ran (--dump-dom)
  std::string log;                   ///< Chromium's stderr
  std::filesystem::path screenshot;  ///< PNG of the window
};

/// Loads `page` (a local file) in a `width`×`height` window, letting its scripts run up to 60 s of virtual
/// time; `work` receives the profile, the log and the screenshot.
inline BrowserLoad load_in_chromium(const std::filesystem::path& chromium, const std::filesystem::path& page,
                                    const std::filesystem::path& work, int width, int height) {
  const auto profile = work / "profile";
  std::filesystem::remove_all(profile);
  std::filesystem::create_directories(profile);
  BrowserLoad r;
  r.screenshot = work / "screenshot.png";
  const auto dom = work / "dom.html", log = work / "chromium.log";
  const std::string command =
      "'" + chromium.string() +
      "' --headless --no-sandbox --disable-gpu --enable-unsafe-swiftshader --disable-quic --no-first-run "
      "--disable-background-networking --disable-component-update --disable-sync --enable-logging=stderr "
      "--v=0 --user-data-dir='" +
      profile.string() + "' --window-size=" + std::to_string(width) + "," + std::to_string(height) +
      " --virtual-time-budget=60000 --screenshot='" + r.screenshot.string() + "' --dump-dom 'file://" +
      std::filesystem::absolute(page).string() + "' > '" + dom.string() + "' 2> '" + log.string() + "'";
  r.exit_code = std::system(command.c_str());
  auto slurp = [](const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  };
  r.dom = slurp(dom);
  r.log = slurp(log);
  std::filesystem::remove_all(profile);
  return r;
}

/// The value of attribute `name` of the first element whose start tag contains `tag_marker`, or "".
inline std::string attribute_of(const std::string& dom, const std::string& tag_marker,
                                const std::string& name) {
  const std::size_t marker = dom.find(tag_marker);
  if (marker == std::string::npos) return "";
  const std::size_t start = dom.rfind('<', marker), end = dom.find('>', marker);
  const std::string tag = dom.substr(start, end - start);
  const std::string key = " " + name + "=\"";
  const std::size_t at = tag.find(key);
  if (at == std::string::npos) return "";
  const std::size_t value = at + key.size();
  return tag.substr(value, tag.find('"', value) - value);
}

}  // namespace glmbslam::test
