#include "bench/shipped_files.h"

#include <algorithm>
#include <filesystem>
#include <system_error>

namespace dw::bench {
namespace {

namespace fs = std::filesystem;

// Whether `program` (a resolved path) is in the folder `tree`, as the file system resolves it.
bool inside(const fs::path& program, const fs::path& tree) {
  std::error_code error;
  const fs::path root = fs::canonical(tree, error);
  if (error) return false;
  return std::mismatch(root.begin(), root.end(), program.begin(), program.end()).first == root.end();
}

}  // namespace

ShippedFiles shipped_files() {
  std::error_code error;
  const fs::path program = fs::read_symlink("/proc/self/exe", error);
  if (!error && !inside(program, DWATCH_BUILD_DIR)) {
    // PREFIX/bin/dwatch -> PREFIX/share/dwatch (DWATCH_SHARE_FROM_BIN: the install's own layout).
    const fs::path share = (program.parent_path() / DWATCH_SHARE_FROM_BIN).lexically_normal();
    return {(share / "scenarios").string(), (share / "scenarios" / "lua").string(), (share / "plot_paper.py").string()};
  }
  return {DWATCH_SOURCE_DIR "/scenarios", DWATCH_SOURCE_DIR "/scenarios/lua",
          DWATCH_SOURCE_DIR "/scripts/plot_paper.py"};
}

}  // namespace dw::bench
