#include "shell/output_files.h"

#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <cctype>
#include <iostream>

namespace dw::shell {
namespace {

// What a path is, to compare two: a device and inode when it exists, else its normalized path.
struct Identity {
  bool exists = false;
  dev_t dev = 0;
  ino_t ino = 0;
  bool null_device = false;  // /dev/null: any number of outputs may go there
  std::string path;
  bool operator==(const Identity& o) const {
    return exists == o.exists && (exists ? dev == o.dev && ino == o.ino : path == o.path);
  }
};

Identity identity(const std::string& path) {
  Identity id;
  struct stat st {};
  if (path == "-" ? ::fstat(STDOUT_FILENO, &st) == 0 : ::stat(path.c_str(), &st) == 0) {
    id.exists = true;
    id.dev = st.st_dev;
    id.ino = st.st_ino;
    id.null_device = S_ISCHR(st.st_mode) && st.st_rdev == makedev(1, 3);
    return id;
  }
  id.path = sim::resolved_path(path);
  return id;
}

std::string spelled(const NamedFile& f) { return f.what + " " + (f.path == "-" ? "- (standard output)" : f.path); }

}  // namespace

std::string file_clash(const std::vector<std::string>& inputs, const std::vector<NamedFile>& outputs,
                       std::string_view where_stdout_goes) {
  std::vector<std::pair<const std::string*, Identity>> in;
  std::vector<std::pair<const NamedFile*, Identity>> out;
  for (const std::string& path : inputs)
    if (!path.empty() && path != "-") in.emplace_back(&path, identity(path));
  for (const NamedFile& f : outputs)
    if (!f.path.empty()) out.emplace_back(&f, identity(f.path));
  std::string clash;
  for (size_t i = 0; i < out.size() && clash.empty(); ++i) {
    for (const auto& [path, id] : in)
      if (clash.empty() && out[i].second == id && !id.null_device)
        clash = spelled(*out[i].first) + (*path == kStandardOutput
                                              ? " would write " + std::string(where_stdout_goes) + " (standard output)"
                                              : " would overwrite the input " + *path);
    for (size_t j = 0; j < i && clash.empty(); ++j)
      if (out[i].second == out[j].second && !out[i].second.null_device)
        clash = spelled(*out[j].first) + " and " + spelled(*out[i].first) + " name one file; give each output its own";
  }
  return clash;
}

bool check_distinct_files(const std::vector<std::string>& inputs, const std::vector<NamedFile>& outputs,
                          std::string_view where_stdout_goes) {
  const std::string clash = file_clash(inputs, outputs, where_stdout_goes);
  if (!clash.empty()) std::cerr << "dwatch: error: " << clash << "\n";
  return clash.empty();
}

std::string file_name_part(std::string_view name) {
  std::string part;
  for (const char c : name.substr(0, 100))
    part += std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' || c == '.' ? c : '_';
  if (part.empty() || part[0] == '.') part.insert(part.begin(), '_');
  return part;
}

bool open_output(const NamedFile& file, std::unique_ptr<sim::OutputFile>& out) {
  if (file.path.empty()) return true;
  std::string error;
  out = sim::OutputFile::open(file.path, &error);
  if (!out) std::cerr << "dwatch: error: " << file.what << ": " << error << "\n";
  return out != nullptr;
}

std::string open_output_apart(const std::vector<std::string>& inputs, const NamedFile& file,
                              std::unique_ptr<sim::OutputFile>& out, std::stop_token stop) {
  if (std::string clash = file_clash(inputs, {file}); !clash.empty()) return clash;
  std::string error;
  out = sim::OutputFile::open(file.path, &error, sim::kOutputWait, std::move(stop));
  return error;
}

bool commit_outputs(const std::vector<sim::OutputFile*>& outputs) {
  bool ok = true;
  for (sim::OutputFile* out : outputs) {
    if (out == nullptr) continue;
    if (std::string error = out->commit(); !error.empty()) {
      // "-" said as the README says it: a closed pipe or a full disk under `--matches -`.
      if (out->path() == "-" && error.rfind("writing - failed", 0) == 0)
        error.replace(0, std::string_view("writing -").size(), "writing standard output");
      std::cerr << "dwatch: error: " << error << "\n";
      ok = false;
    }
  }
  return ok;
}

}  // namespace dw::shell
