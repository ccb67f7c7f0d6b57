// Headless chromium for the browser tests, driven through chromedriver's W3C WebDriver HTTP API
// with a few plain requests (httplib's client): start a session, open a page, run a script.
#pragma once

#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "tests/daemon/daemon_process.hpp"
#include "tests/tcp_ports.hpp"

// httplib brings <resolv.h>, whose _res macro breaks Eigen's declarations: include this header
// after every header that includes Eigen.
#include <httplib.h>

namespace skyroute::testing {

// Polls until done() or timeout_s passes; returns done().
inline bool eventually(const std::function<bool()>& done, double timeout_s) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (!done()) {
    if (std::chrono::steady_clock::now() >= deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  return true;
}

class WebDriver {
 public:
  static constexpr const char* kChromium = "/usr/bin/chromium";
  static constexpr const char* kChromedriver = "/usr/bin/chromedriver";

  // Starts chromedriver and a headless chromium session with a fresh profile; null and *why set
  // when that fails.
  static std::unique_ptr<WebDriver> open(std::string* why) {
    for (const char* program : {kChromium, kChromedriver}) {
      if (!std::filesystem::exists(program)) {
        *why = std::string(program) + " is missing: install chromium and chromium-driver (scripts/setup.sh does)";
        return nullptr;
      }
    }
    std::unique_ptr<WebDriver> d(new WebDriver());
    d->profile_ = std::filesystem::temp_directory_path() / ("skyroute_chromium_" + std::to_string(::getpid()));
    std::filesystem::create_directories(d->profile_);
    const int port = freeTcpPort();
    d->driver_ = ChildProcess::spawn({kChromedriver, "--port=" + std::to_string(port)}, "chromedriver");
    d->http_ = std::make_unique<httplib::Client>("127.0.0.1", port);
    d->http_->set_read_timeout(60, 0);
    const bool ready = eventually(
        [&] {
          auto res = d->http_->Get("/status");
          return res && res->status == 200 && nlohmann::json::parse(res->body)["value"]["ready"] == true;
        },
        20.0);
    if (!ready) {
      *why = "chromedriver did not become ready: " + d->driver_.err();
      return nullptr;
    }
    const nlohmann::json args = {"--headless",
                                 "--no-sandbox",
                                 "--disable-gpu",
                                 "--disable-quic",
                                 "--no-first-run",
                                 "--disable-background-networking",
                                 "--disable-component-update",
                                 "--disable-sync",
                                 "--window-size=1400,1000",
                                 "--user-data-dir=" + d->profile_.string()};
    const nlohmann::json capabilities = {
        {"capabilities",
         {{"alwaysMatch", {{"browserName", "chrome"}, {"goog:chromeOptions", {{"binary", kChromium}, {"args", args}}}}}}}};
    auto session = d->call("POST", "/session", capabilities);
    if (!session || !session->contains("sessionId")) {
      *why = "chromedriver did not start chromium: " + (session ? session->dump() : std::string("no answer"));
      return nullptr;
    }
    d->session_ = (*session)["sessionId"].get<std::string>();
    return d;
  }

  ~WebDriver() {
    if (!session_.empty()) (void)call("DELETE", "/session/" + session_, nullptr);  // closes chromium
    if (http_) (void)http_->Get("/shutdown");
    if (driver_.wait(10.0) < 0) driver_.signal(SIGKILL);
    std::error_code ignored;
    std::filesystem::remove_all(profile_, ignored);
  }

  bool navigate(const std::string& url) { return call("POST", "/session/" + session_ + "/url", {{"url", url}}).has_value(); }

  // Runs a script in the page ("return ..." gives its value); nullopt when the call failed.
  std::optional<nlohmann::json> script(const std::string& body) {
    return call("POST", "/session/" + session_ + "/execute/sync", {{"script", body}, {"args", nlohmann::json::array()}});
  }

 private:
  WebDriver() = default;

  // One WebDriver command; its "value", or nullopt on a transport or WebDriver error.
  std::optional<nlohmann::json> call(const std::string& method, const std::string& path, const nlohmann::json& body) {
    httplib::Result res = method == "POST"     ? http_->Post(path.c_str(), body.dump(), "application/json")
                          : method == "DELETE" ? http_->Delete(path.c_str())
                                               : http_->Get(path.c_str());
    if (!res || res->status != 200) return std::nullopt;
    const nlohmann::json answer = nlohmann::json::parse(res->body, nullptr, false);
    if (answer.is_discarded() || !answer.contains("value")) return std::nullopt;
    return answer["value"];
  }

  ChildProcess driver_;
  std::unique_ptr<httplib::Client> http_;
  std::string session_;
  std::filesystem::path profile_;
};

}  // namespace skyroute::testing
