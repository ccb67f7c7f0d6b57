// Fuzzes the Moving AI benchmark loaders (`skyroute grid solve --map M --scen S`): the input is a
// .map, then optionally a line "%%" and a .scen. A map that loads is searched as the command does
// (A* for the first few problems of the scenario, whatever cells they name).
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>
#include <string_view>

#include "planning/grid/grid_search.hpp"
#include "terrain/movingai.hpp"

namespace {

constexpr std::string_view kSeparator = "\n%%\n";
constexpr std::size_t kProblemsSearched = 4;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace skyroute;
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  const std::size_t split = input.find(kSeparator);
  std::istringstream map_text(std::string(input.substr(0, split)));
  auto grid = parseMovingAiMap(map_text, "fuzz.map");
  if (split == std::string_view::npos) return 0;
  std::istringstream scen_text(std::string(input.substr(split + kSeparator.size())));
  auto problems = parseMovingAiScenario(scen_text, "fuzz.map.scen");
  if (!grid || !problems) return 0;
  for (std::size_t i = 0; i < std::min(problems->size(), kProblemsSearched); ++i)
    (void)astarSearch(*grid, (*problems)[i].start, (*problems)[i].goal);
  return 0;
}
