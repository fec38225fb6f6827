// Files named on the command line. Outputs are opened before a run, so that a bad path costs
// nothing and is bad input, and committed after it (sim::OutputFile: a failed write destroys
// nothing), so that a failed write is a runtime failure. Before anything runs, two outputs naming
// one file, or an output naming an input, are bad input: compared by device and inode, so that
// `./x`, a symlink or /dev/stdout next to `-` are caught as well.
#pragma once

#include <memory>
#include <ostream>
#include <stop_token>
#include <string>
#include <string_view>
#include <vector>

#include "sim/output_file.h"

namespace dw::shell {

// A file as the command line names it: `what` says which ("--matches", "the scenario").
struct NamedFile {
  std::string what;
  std::string path;  // "-" is standard output; empty: not given
};

// Among the inputs, what standard output is (the session's answers): no output may write there.
inline constexpr std::string_view kStandardOutput = "/dev/stdout";

// What is wrong, naming the two, when two outputs name one file or an output names one of the
// inputs (files read: the scenario, a script, a trace, watchpoint files; kStandardOutput, said as
// `where_stdout_goes`: "where the answers go"); empty when nothing is.
std::string file_clash(const std::vector<std::string>& inputs, const std::vector<NamedFile>& outputs,
                       std::string_view where_stdout_goes = "where the answers go");
// False, with file_clash's message on stderr, when there is one.
bool check_distinct_files(const std::vector<std::string>& inputs, const std::vector<NamedFile>& outputs,
                          std::string_view where_stdout_goes = "where the answers go");

// `name` (a scenario's, from its file) made fit to be part of a file name in the working
// directory: every character but letters, digits, '-', '_' and '.' becomes '_', and it never
// starts with '.', so that it names no other directory and no hidden file.
std::string file_name_part(std::string_view name);

// Opens `file` for writing unless its path is empty. False, with the error on stderr, when it
// cannot be written.
bool open_output(const NamedFile& file, std::unique_ptr<sim::OutputFile>& out);
// The stream of an open output, or nullptr.
inline std::ostream* stream_of(const std::unique_ptr<sim::OutputFile>& out) { return out ? &out->stream() : nullptr; }
// Opens `file` for writing, once it names none of `inputs`: empty, or what is wrong (for a
// session's command, which answers with it rather than printing it).
// A stop requested on `stop` (a signal) ends its wait for a FIFO's reader, or for room to write.
std::string open_output_apart(const std::vector<std::string>& inputs, const NamedFile& file,
                              std::unique_ptr<sim::OutputFile>& out, std::stop_token stop = {});
// Commits every open output; false, with the error on stderr, when one failed.
bool commit_outputs(const std::vector<sim::OutputFile*>& outputs);

}  // namespace dw::shell
