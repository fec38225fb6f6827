// The commands that write a file (render, record, save): each opened apart from the session's
// inputs and committed whole (sim/output_file.h), so that a failed or stopped command leaves the
// file it would replace as it was.
#include <sys/stat.h>

#include <algorithm>
#include <memory>

#include "scenarios/saved_scenario.h"
#include "shell/output_files.h"
#include "shell/shell.h"
#include "shell/view_image.h"
#include "sim/why.h"

namespace dw::shell {

render::Scene Shell::scene() {
  const int64_t t = std::max<int64_t>(0, session_.current());
  render::SceneSettings settings = scene_settings(scenario_, "");
  settings.title = scenario_.name + "  \xC2\xB7  step " + std::to_string(t);
  return render::build_scene(session_.model(), session_.state(), groups_at(session_, t, Highlight::First), settings);
}

Shell::Answer Shell::render_file(const Command& cmd, const sim::Control& control, nlohmann::ordered_json answer) {
  const NamedFile file{"render", cmd.name};
  std::unique_ptr<sim::OutputFile> out;
  if (cmd.name == "-") return failed("render needs a file name");
  if (std::string error = open_output_apart(scenario_.inputs, file, out, control.stop); !error.empty())
    return failed(error);
  const render::Scene view = scene();
  if (std::string error = write_view(view, *out, cmd.width, cmd.height); !error.empty()) return failed(error);
  // A signal while it drew stops the script here: the file it would replace stays as it was.
  if (control.stopped()) return failed("cancelled");
  if (std::string error = out->commit(); !error.empty()) return failed(error);
  answer["render"] = cmd.name;
  answer["t"] = std::max<int64_t>(0, session_.current());
  answer["width"] = cmd.width;
  answer["height"] = cmd.height;
  answer["groups"] = view.groups.size();
  return answer;
}

Shell::Answer Shell::record_file(const Command& cmd, const sim::Control& control, nlohmann::ordered_json answer) {
  const NamedFile file{"record", cmd.name};
  std::unique_ptr<sim::OutputFile> out;
  if (std::string error = open_output_apart(scenario_.inputs, file, out, control.stop); !error.empty())
    return failed(error);
  const std::string recorded = cmd.messages ? sim::record_with_messages(session_, out->stream(), control)
                                            : session_.record(out->stream(), control);
  if (const std::string& error = recorded; !error.empty()) {
    if (error == "cancelled") return failed(error);  // the temporary goes with `out`
    // The file knows why its writing failed (a full disk): its reason, rather than the stream's.
    const std::string reason = out->commit();
    return failed(reason.empty() ? error : reason);
  }
  if (std::string error = out->commit(); !error.empty()) return failed(error);
  answer["record"] = cmd.name;
  answer["steps"] = session_.latest() + 1;
  if (cmd.messages) answer["messages"] = true;
  answer["interventions"] = session_.interventions().size();
  return answer;
}

Shell::Answer Shell::save_file(const Command& cmd, nlohmann::ordered_json answer) {
  if (cmd.name == "-") return failed("save needs a file name");
  struct stat st {};
  // A folder is no file to overwrite: opening it says so ("Is a directory").
  if (!cmd.overwrite && ::lstat(cmd.name.c_str(), &st) == 0 && !S_ISDIR(st.st_mode))
    return failed(cmd.name + " exists; 'save " + command_word(cmd.name) + " overwrite' replaces it");
  std::string why;
  const std::optional<std::string> text = scenarios::saved_scenario(scenario_, session_, bookmarks_, cmd.name, &why);
  if (!text) return failed(why);
  std::unique_ptr<sim::OutputFile> out;
  if (std::string error = open_output_apart(scenario_.inputs, {"save", cmd.name}, out); !error.empty())
    return failed(error);
  out->stream() << *text;
  if (std::string error = out->commit(); !error.empty()) return failed(error);
  answer["save"] = cmd.name;
  answer["watches"] = session_.watches().size();
  answer["interventions"] = session_.interventions().size();
  if (!bookmarks_.all().empty()) answer["bookmarks"] = bookmarks_.all().size();
  return answer;
}

}  // namespace dw::shell
