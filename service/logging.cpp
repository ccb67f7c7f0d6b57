#include "service/logging.hpp"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <memory>

#include <spdlog/pattern_formatter.h>
#include <spdlog/sinks/stdout_sinks.h>
#include <spdlog/spdlog.h>

namespace skyroute {
namespace {

// One JSON object per line: time, level, pid, then the event's own fields. Values that read as
// numbers or booleans become JSON numbers and booleans, so a collector can filter and sum them.
class JsonEventFormatter final : public spdlog::formatter {
 public:
  void format(const spdlog::details::log_msg& msg, spdlog::memory_buf_t& dest) override {
    nlohmann::ordered_json line;
    const auto since_epoch = msg.time.time_since_epoch();
    const std::time_t seconds = std::chrono::duration_cast<std::chrono::seconds>(since_epoch).count();
    const long micros = static_cast<long>(std::chrono::duration_cast<std::chrono::microseconds>(since_epoch).count() % 1000000);
    std::tm utc{};
    gmtime_r(&seconds, &utc);
    char stamp[64];
    const std::size_t n = std::strftime(stamp, sizeof stamp, "%Y-%m-%dT%H:%M:%S", &utc);
    std::snprintf(stamp + n, sizeof stamp - n, ".%06ldZ", micros);
    line["time"] = stamp;
    line["level"] = std::string(spdlog::level::to_string_view(msg.level).data(),
                                spdlog::level::to_string_view(msg.level).size());
    line["pid"] = static_cast<long>(::getpid());
    const nlohmann::ordered_json fields = logEventFields(std::string_view(msg.payload.data(), msg.payload.size()));
    for (auto field = fields.cbegin(); field != fields.cend(); ++field) {
      if (!line.contains(field.key())) line[field.key()] = field.value();
    }
    const std::string text = line.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
    dest.append(text.data(), text.data() + text.size());
    dest.push_back('\n');
  }
  std::unique_ptr<formatter> clone() const override { return std::make_unique<JsonEventFormatter>(); }
};

nlohmann::ordered_json typedValue(const std::string& text) {
  if (text == "true") return true;
  if (text == "false") return false;
  if (!text.empty() && text.find_first_not_of("0123456789+-.eE") == std::string::npos) {
    try {
      std::size_t used = 0;
      if (text.find_first_of(".eE") == std::string::npos) {
        const long long whole = std::stoll(text, &used);
        if (used == text.size()) return whole;
      } else {
        const double real = std::stod(text, &used);
        if (used == text.size() && std::isfinite(real)) return real;
      }
    } catch (const std::exception&) {
    }
  }
  return text;
}

}  // namespace

nlohmann::ordered_json logEventFields(std::string_view message) {
  nlohmann::ordered_json fields = nlohmann::ordered_json::object();
  std::size_t at = 0;
  const auto skipSpaces = [&] {
    while (at < message.size() && message[at] == ' ') ++at;
  };
  skipSpaces();
  while (at < message.size()) {
    const std::size_t eq = message.find('=', at);
    const std::size_t space = message.find(' ', at);
    if (eq == std::string_view::npos || (space != std::string_view::npos && space < eq) || eq == at) break;
    const std::string key(message.substr(at, eq - at));
    at = eq + 1;
    std::string value;
    bool quoted = false;
    if (at < message.size() && message[at] == '"') {  // "..." with \" and \\ escapes
      quoted = true;
      ++at;
      while (at < message.size() && message[at] != '"') {
        if (message[at] == '\\' && at + 1 < message.size()) ++at;
        value.push_back(message[at++]);
      }
      if (at >= message.size()) return {{"msg", std::string(message)}};  // unterminated: keep the line
      ++at;
    } else {
      const std::size_t end = std::min(message.find(' ', at), message.size());
      value = std::string(message.substr(at, end - at));
      at = end;
    }
    fields[key] = quoted ? nlohmann::ordered_json(value) : typedValue(value);
    skipSpaces();
  }
  if (at < message.size()) {  // free text after (or instead of) the fields
    if (fields.empty()) return {{"msg", std::string(message)}};
    fields["msg"] = std::string(message.substr(at));
  }
  return fields;
}

Status setupLogging(const std::string& level, const std::string& format) {
  const spdlog::level::level_enum parsed = spdlog::level::from_str(level);
  if (parsed == spdlog::level::off && level != "off") {
    return make_error(ErrorCode::kInvalidArgument, "log.level", "'" + level + "' is not trace, debug, info, warn or error");
  }
  auto logger = std::make_shared<spdlog::logger>("skyroute", std::make_shared<spdlog::sinks::stderr_sink_mt>());
  if (format == "json") {
    logger->set_formatter(std::make_unique<JsonEventFormatter>());
  } else if (format == "text") {
    logger->set_pattern("%Y-%m-%dT%H:%M:%S.%e %^%l%$ %v");
  } else {
    return make_error(ErrorCode::kInvalidArgument, "log.format", "'" + format + "' is not text or json");
  }
  logger->set_level(parsed);
  logger->flush_on(spdlog::level::info);  // a supervisor sees each event as it happens
  spdlog::set_default_logger(std::move(logger));
  return Status::success();
}

}  // namespace skyroute
