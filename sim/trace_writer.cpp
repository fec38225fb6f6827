#include <fstream>
#include <nlohmann/json.hpp>

#include "sim/trace.h"

namespace dw::sim {

bool write_trace(const Trace& trace, const std::string& path) {
  std::ofstream out(path, std::ios::binary);
  if (!out) return false;
  const watch::Universe& u = trace.universe();
  // Variable names are escaped once by nlohmann; the numbers are written per line.
  std::vector<std::string> keys;
  for (const std::string& v : u.variables) keys.push_back(nlohmann::json(v).dump() + ":");
  out << "{\"wptrace\":1}\n";
  std::string line;
  for (int64_t t = 0; t < trace.step_count(); ++t) {
    const watch::Frame f = trace.frame(t);
    for (uint32_t m = 0; m < u.module_count(); ++m) {
      if (!f.present[m]) continue;
      line = "{\"t\":" + std::to_string(t) + ",\"m\":" + std::to_string(u.module_ids[m]) + ",\"vars\":{";
      bool first = true;
      for (size_t v = 0; v < keys.size(); ++v) {
        const size_t at = static_cast<size_t>(m) * f.variable_count + v;
        if (!f.has_value[at]) continue;
        line += (first ? "" : ",") + keys[v] + std::to_string(f.values[at]);
        first = false;
      }
      line += "},\"nbrs\":[";
      first = true;
      for (uint32_t n : f.neighbors(m)) {
        line += (first ? "" : ",") + std::to_string(u.module_ids[n]);
        first = false;
      }
      line += "]}\n";
      out << line;
    }
  }
  return static_cast<bool>(out);
}

}  // namespace dw::sim
