// Three robots in a line, 0 - 1 - 2, two steps of a log: two leaders within two hops at step 1.
// Prints each match as "t a b c" and the number of matches; a bad watchpoint's diagnostic.
#include <cstdint>
#include <iostream>
#include <vector>

#include "watch/make_detector.h"
#include "watch/watchpoint.h"

int main(int argc, char** argv) {
  const std::string text = argc > 1 ? argv[1] : "modules(a b c); (a.isLeader = 1) and (c.isLeader = 1)";
  auto compiled = dw::watch::compile_watchpoint("leaders", dw::watch::SourceText("<argument>", text));
  if (auto* error = std::get_if<dw::watch::CompileError>(&compiled)) {
    std::cerr << error->format();
    return 2;
  }
  const auto& watchpoint = std::get<dw::watch::Watchpoint>(compiled);
  dw::watch::Universe universe{{0, 1, 2}, {"isLeader"}};
  int matches = 0;
  auto detector = dw::watch::make_detector(
      dw::watch::Algorithm::Centralized, watchpoint, universe, {},
      [&](int64_t t, std::span<const dw::watch::ModuleId> ids, std::span<const dw::watch::Value>) {
        for (size_t i = 0; i < ids.size(); i += 3, ++matches)
          std::cout << t << " " << ids[i] << " " << ids[i + 1] << " " << ids[i + 2] << "\n";
      });
  const std::vector<uint8_t> present{1, 1, 1}, has{1, 1, 1};
  const std::vector<uint32_t> begin{0, 1, 3, 4}, nbrs{1, 0, 2, 1};
  const std::vector<std::vector<int64_t>> leaders{{1, 0, 0}, {1, 0, 1}};
  for (int64_t t = 0; t < 2; ++t) {
    dw::watch::Frame f;
    f.step = t;
    f.present = present;
    f.values = leaders[size_t(t)];
    f.has_value = has;
    f.nbr_begin = begin;
    f.nbrs = nbrs;
    f.variable_count = 1;
    detector->observe(f);
  }
  std::cout << matches << " matches\n";
  return 0;
}
