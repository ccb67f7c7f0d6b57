#include "service/dds/service_instance.hpp"

#include <unistd.h>

#include <array>
#include <chrono>
#include <ctime>
#include <random>

#include "service/dds/dds_entities.hpp"
#include "service/mission_types.hpp"
#include "service/number_text.hpp"
#include "service/text_bounds.hpp"

namespace skyroute::dds {
namespace {

constexpr std::string_view kTag = "skyrouted-instance/1";

std::string hostName() {
  std::array<char, 256> name{};
  if (::gethostname(name.data(), name.size() - 1) != 0) return "unknown-host";
  return name.data();
}

std::string utcText(std::int64_t utc_ns) {
  const std::time_t seconds = static_cast<std::time_t>(utc_ns / 1000000000);
  std::tm tm{};
  gmtime_r(&seconds, &tm);
  char buffer[32];
  std::strftime(buffer, sizeof buffer, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buffer;
}

}  // namespace

ServiceInstance ServiceInstance::current(const std::string& service_id, double heartbeat_period_s,
                                         const std::string& role) {
  ServiceInstance s;
  s.service_id = service_id;
  s.role = role;
  s.heartbeat_period_s = heartbeat_period_s;
  s.host = hostName();
  s.pid = ::getpid();
  s.started_utc_ns = utcNowNs();
  std::random_device device;
  std::mt19937_64 random((static_cast<std::uint64_t>(device()) << 32) ^ device() ^
                         static_cast<std::uint64_t>(s.started_utc_ns));
  static constexpr char kHex[] = "0123456789abcdef";
  std::uint64_t bits = random();
  for (int i = 0; i < 16; ++i, bits >>= 4) s.instance_id.push_back(kHex[bits & 0xf]);
  return s;
}

std::string ServiceInstance::userData() const {
  return std::string(kTag) + ";service_id=" + service_id + ";instance=" + instance_id + ";host=" + host +
         ";pid=" + std::to_string(pid) + ";started_utc_ns=" + std::to_string(started_utc_ns) +
         ";heartbeat_period_s=" + numberText(heartbeat_period_s, 9) + ";role=" + role +
         (shard_group.empty() ? std::string() : ";shard_group=" + shard_group) +
         (past_coverage.empty() ? std::string() : ";coverage=" + coverageText(past_coverage));
}

std::optional<ServiceInstance> ServiceInstance::fromUserData(std::string_view text) {
  if (text.substr(0, kTag.size()) != kTag) return std::nullopt;
  ServiceInstance s;
  std::size_t at = kTag.size();
  while (at < text.size()) {
    const std::size_t end = std::min(text.find(';', at + 1), text.size());
    const std::string_view field = text.substr(at + 1, end - at - 1);
    const std::size_t eq = field.find('=');
    if (eq != std::string_view::npos) {
      const std::string_view key = field.substr(0, eq);
      const std::string value(field.substr(eq + 1));
      try {
        if (key == "service_id") s.service_id = value;
        if (key == "instance") s.instance_id = value;
        if (key == "host") s.host = value;
        if (key == "pid") s.pid = std::stoll(value);
        if (key == "started_utc_ns") s.started_utc_ns = std::stoll(value);
        if (key == "heartbeat_period_s") s.heartbeat_period_s = std::stod(value);
        if (key == "role" && !value.empty()) s.role = value;
        if (key == "shard_group") s.shard_group = value;
        if (key == "coverage") {
          // Unreadable: as if it advertised none (it then owns only what its current life read).
          if (auto past = coverageFromText(value)) s.past_coverage = std::move(*past);
        }
      } catch (const std::exception&) {
        return std::nullopt;
      }
    }
    at = end;
  }
  // Another participant's USER_DATA is untrusted text: its ids must be bounded ids, its other
  // words bounded names (text_bounds.hpp), or it is no skyroute service.
  if (!isValidId(s.service_id) || !isValidId(s.instance_id)) return std::nullopt;
  if (checkName(s.host, "host") || checkName(s.role, "role") || checkOptionalId(s.shard_group, "shard_group"))
    return std::nullopt;
  return s;
}

bool ServiceInstance::precedes(const ServiceInstance& other) const {
  if (started_utc_ns != other.started_utc_ns) return started_utc_ns < other.started_utc_ns;
  return instance_id < other.instance_id;
}

std::string ServiceInstance::describe() const {
  return "instance " + instance_id + " (" + role + ", pid " + std::to_string(pid) + " on " + host + ", started " +
         utcText(started_utc_ns) + ")";
}

std::optional<ServiceInstance> announcedInstance(const dds_qos_t* qos) {
  if (qos == nullptr) return std::nullopt;
  void* value = nullptr;
  std::size_t size = 0;
  if (!dds_qget_userdata(qos, &value, &size) || value == nullptr) return std::nullopt;
  auto instance = ServiceInstance::fromUserData(std::string_view(static_cast<const char*>(value), size));
  dds_free(value);
  return instance;
}

std::vector<ServiceInstance> discoveredInstances(dds_entity_t participant_reader) {
  std::vector<ServiceInstance> out;
  constexpr std::size_t kBatch = 64;
  std::array<void*, kBatch> loans{};
  std::array<dds_sample_info_t, kBatch> infos{};
  // Read, not take: the reader keeps every participant's latest state.
  const dds_return_t n = dds_read(participant_reader, loans.data(), infos.data(), kBatch, kBatch);
  if (n <= 0) return out;
  for (dds_return_t i = 0; i < n; ++i) {
    if (!infos[i].valid_data || infos[i].instance_state != DDS_IST_ALIVE) continue;
    const auto* participant = static_cast<const dds_builtintopic_participant_t*>(loans[i]);
    if (auto instance = announcedInstance(participant->qos)) out.push_back(std::move(*instance));
  }
  (void)dds_return_loan(participant_reader, loans.data(), n);
  return out;
}

std::vector<ServiceInstance> matchedInstances(dds_entity_t heartbeat_reader) {
  std::vector<ServiceInstance> out;
  std::array<dds_instance_handle_t, 64> handles{};
  const dds_return_t n = dds_get_matched_publications(heartbeat_reader, handles.data(), handles.size());
  if (n <= 0) return out;
  for (dds_return_t i = 0; i < std::min<dds_return_t>(n, static_cast<dds_return_t>(handles.size())); ++i) {
    const Endpoint endpoint = matchedPublication(heartbeat_reader, handles[i]);
    if (!endpoint) continue;
    if (auto instance = announcedInstance(endpoint->qos)) out.push_back(std::move(*instance));
  }
  return out;
}

}  // namespace skyroute::dds
