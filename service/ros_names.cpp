#include "service/ros_names.hpp"

#include <cctype>
#include <cstdint>
#include <cstdio>
#include <vector>

namespace skyroute {

namespace {

bool allowedChar(char c) {
  return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_' || c == '/';
}

std::vector<std::string_view> tokens(std::string_view text) {
  std::vector<std::string_view> out;
  std::size_t start = 0;
  for (;;) {
    const std::size_t slash = text.find('/', start);
    out.push_back(text.substr(start, slash == std::string_view::npos ? std::string_view::npos : slash - start));
    if (slash == std::string_view::npos) return out;
    start = slash + 1;
  }
}

// FNV-1a: a stable hash (std::hash may differ between builds), so a suffixed name survives restarts.
std::uint32_t fnv1a(std::string_view text) {
  std::uint32_t h = 2166136261u;
  for (char c : text) {
    h ^= static_cast<unsigned char>(c);
    h *= 16777619u;
  }
  return h;
}

}  // namespace

bool isValidRosName(std::string_view text) {
  if (text.empty()) return false;
  for (char c : text) {
    if (!allowedChar(c)) return false;
  }
  for (std::string_view token : tokens(text)) {
    if (token.empty() || std::isdigit(static_cast<unsigned char>(token.front())) != 0) return false;
  }
  return true;
}

std::string sanitiseRosName(std::string_view vehicle_id) {
  std::string replaced(vehicle_id);
  for (char& c : replaced) {
    if (!allowedChar(c)) c = '_';
  }
  std::string out;
  for (std::string_view token : tokens(replaced)) {
    if (token.empty()) continue;
    if (!out.empty()) out += '/';
    if (std::isdigit(static_cast<unsigned char>(token.front())) != 0) out += '_';
    out += token;
  }
  return out.empty() ? "_" : out;
}

std::string RosNameRegistry::hashedName(const std::string& vehicle_id) const {
  char suffix[16];
  std::snprintf(suffix, sizeof suffix, "_%08x", fnv1a(vehicle_id));
  const std::string base = sanitiseRosName(vehicle_id) + suffix;
  // A further clash needs a hash collision on top of a name clash; count up rather than fail.
  std::string name = base;
  for (int n = 2; vehicle_of_name_.count(name) > 0; ++n) name = base + "_" + std::to_string(n);
  return name;
}

RosNameRegistry::Assignment RosNameRegistry::assign(const std::string& vehicle_id) {
  if (const std::string* known = nameOf(vehicle_id)) return {*known, std::nullopt, {}};
  const std::string wanted = sanitiseRosName(vehicle_id);
  Assignment out;
  auto holder = vehicle_of_name_.find(wanted);
  if (holder == vehicle_of_name_.end()) {
    out.name = wanted;
  } else if (wanted == vehicle_id) {
    // The name is this vehicle's own id: the sanitised holder moves to a hashed name.
    const std::string displaced = holder->second;
    out.displaced_vehicle = displaced;
    out.displaced_name = hashedName(displaced);
    vehicle_of_name_[out.displaced_name] = displaced;
    name_of_vehicle_[displaced] = out.displaced_name;
    out.name = wanted;
  } else {
    out.name = hashedName(vehicle_id);
  }
  vehicle_of_name_[out.name] = vehicle_id;
  name_of_vehicle_[vehicle_id] = out.name;
  return out;
}

const std::string* RosNameRegistry::nameOf(const std::string& vehicle_id) const {
  auto it = name_of_vehicle_.find(vehicle_id);
  return it == name_of_vehicle_.end() ? nullptr : &it->second;
}

}  // namespace skyroute
