// What the window sends the session and reads back: lines of the session language, carried out by
// the worker; their answers on the status line (a pause stops playing and selects its group); the
// Readout read between the worker's jobs; and playing, steps asked for at the chosen speed.
#include <algorithm>

#include "app/view/debugger.h"

namespace dw::view {
namespace {

// Steps a request asks for when playing as fast as possible adapt so that one takes about this.
constexpr double kFastRequestSeconds = 0.02;

}  // namespace

void Debugger::send(const std::string& line) {
  // Parsed on the worker too: checking a command reads the session (a push needs bodies), which
  // only the job that holds it may do.
  worker_->submit([this, line](sim::Session&, const sim::Control& control) {
    Answer a{line, {}, {}};
    const auto start = std::chrono::steady_clock::now();
    const watch::SourceText source("<window>", line);
    auto parsed = shell_.parse(source, 0, 1);
    if (auto* ds = std::get_if<std::vector<watch::Diagnostic>>(&parsed)) {
      a.error = watch::format_diagnostics(source, *ds);
    } else if (auto& command = std::get<std::optional<shell::Command>>(parsed)) {
      try {
        auto result = shell_.execute(*command, control);
        if (auto* error = std::get_if<std::string>(&result)) a.error = *error;
        else a.json = std::move(std::get<nlohmann::ordered_json>(result));
      } catch (const std::exception& e) {  // a program failed: the session stays where it got to
        a.error = e.what();
      }
    }
    last_job_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::lock_guard lock(answers_mutex_);
    answers_.push_back(std::move(a));
  });
}

void Debugger::apply(const std::vector<std::string>& commands) {
  for (const std::string& c : commands) send(c);
}

void Debugger::status(std::string message, bool failed) {
  while (!message.empty() && message.back() == '\n') message.pop_back();
  status_ = std::move(message);
  status_failed_ = failed;
}

void Debugger::refresh_readout() {
  // Answers first: a pause stops playing and selects the group it matched.
  std::optional<std::pair<std::string, int64_t>> paused;
  {
    std::lock_guard lock(answers_mutex_);
    for (; answers_seen_ < answers_.size(); ++answers_seen_) {
      const Answer& a = answers_[answers_seen_];
      if (!a.error.empty()) {
        status(a.line + ": " + a.error, true);
        model_.playing = false;
        // A save that would overwrite a file: the panel asks before sending it again.
        if (a.line.rfind("save ", 0) == 0 && a.error.find(" exists; ") != std::string::npos) save_refused_ = save_sent_;
        continue;
      }
      // A pause, or the match a run was asked to stop at: the group is shown the same way.
      const char* stop = a.json.contains("paused") && !a.json["paused"].is_null()     ? "paused"
                         : a.json.contains("matched") && !a.json["matched"].is_null() ? "matched"
                                                                                      : nullptr;
      if (stop) {
        model_.playing = false;
        const auto& p = a.json[stop];
        paused.emplace(p.value("watch", ""), p.value("t", int64_t{0}));
        paused_on_ = stop == std::string_view("paused") ? p.value("watch", "") : "";
        status(answer_words(a.json));
      } else {
        if (a.json.contains("current")) paused_on_.clear();
        if (!model_.playing) status(answer_words(a.json));
      }
      if (a.json.value("cmd", "") == "why") show_why(a.json, a.line);  // the Why panel draws it
      if (a.json.value("cmd", "") == "diff") diff_ = a.json;           // the diff tab lists it
    }
  }
  const uint64_t version = worker_->finished();
  if (!paused && version == readout_.version && !readout_stale_) return;
  const bool read = worker_->try_read([&](sim::Session& s) {
    if (paused) {
      const int w = s.watch_index(paused->first);
      if (w >= 0) {
        const auto [first, last] = s.matches(uint32_t(w)).at(paused->second);
        if (first < last) {
          model_.selected_match = MatchRef{uint32_t(w), first};
          const size_t k = size_t(s.watches()[uint32_t(w)].hosted.watchpoint.program.slot_count());
          if (k > 0) {  // a zero-slot match (docs/design.md §4c) has no module to select
            model_.selected = s.matches(uint32_t(w)).slots[first * k];
            model_.reveal_group = true;
          }
        }
      }
    }
    ReadoutRequest request{version, module_window_ ? &*module_window_ : nullptr, timeline_, timeline_columns_};
    request.group_window = group_window_ ? &*group_window_ : nullptr;
    request.group_series = group_series_ ? &*group_series_ : nullptr;
    // While playing, the matches table is read again twice a second, not at every step.
    const auto now = std::chrono::steady_clock::now();
    // The rows depend only on the filter and the match lists, which a seek leaves as they are.
    std::string rows_key = std::to_string(model_.filter.watch) + "|" +
                           (model_.filter.module ? std::to_string(*model_.filter.module) : "-") + "|" +
                           std::to_string(int(model_.filter.order)) + std::to_string(model_.filter.descending) + "|" +
                           std::to_string(s.interventions().size());
    for (uint32_t w = 0; w < s.watches().size(); ++w)
      rows_key += "|" + s.watches()[w].hosted.watchpoint.source->text() + "#" + std::to_string(s.matches(w).size());
    if (rows_key == rows_key_ || (model_.playing && now - rows_read_at_ < std::chrono::milliseconds(500))) {
      request.keep_rows = &readout_;
    } else {
      rows_read_at_ = now;
      rows_key_ = std::move(rows_key);
    }
    Readout next = read_readout(s, scenario_, model_, request);
    next.bookmarks = shell_.bookmarks().all();  // changed only by jobs, which hold the session too
    readout_ = std::move(next);
  });
  if (!read) return;  // a job runs: the last Readout stays on screen
  // A program failure, new: its module is selected (the run stands at the last step that went through).
  if (readout_.failure && (!shown_failure_ || shown_failure_->step != readout_.failure->step ||
                           shown_failure_->module != readout_.failure->module)) {
    model_.selected = readout_.failure->module;
    model_.playing = false;
  }
  shown_failure_ = readout_.failure;
  readout_stale_ = false;
  drawn_key_.clear();

  ask_for_history();
}

// The jobs that read what needs the history, off the frame loop, when what they last read is not
// what the Readout shows.
void Debugger::ask_for_history() {
  // The inspector's history of the selected module, when it is not this branch's up to the latest.
  if (model_.selected && !model_.playing && !module_window_asked_ && readout_.at.current >= 0 &&
      !(module_window_ && module_window_->module == *model_.selected && module_window_->to == readout_.at.latest &&
        module_window_->interventions == readout_.interventions.size())) {
    module_window_asked_ = true;
    const sim::ModuleId m = *model_.selected;
    worker_->submit(
        [this, m](sim::Session& s, const sim::Control& control) {
          auto w = read_module_window(s, m, ReadoutLimits{}.plot_steps, control);
          if (w) module_window_ = std::move(*w);
          module_window_asked_ = false;
        },
        /*background=*/true);
  }
  // The Group tab's step before and pins, when they are not this group's at this step.
  if (readout_.group && !model_.playing && !group_window_asked_ && readout_.at.current >= 0 &&
      !(group_window_ && group_window_->holds(readout_.at.current, readout_.at.latest, readout_.interventions.size(),
                                              *readout_.group, model_.pins))) {
    group_window_asked_ = true;
    worker_->submit(
        [this, modules = readout_.group->modules, slots = readout_.group->slots, pins = model_.pins](
            sim::Session& s, const sim::Control& control) {
          auto w = read_group_window(s, modules, slots, pins, control);
          if (w) group_window_ = std::move(*w);
          group_window_asked_ = false;
        },
        /*background=*/true);
  }
  // The group's lines in the Module plot, when the selected module is in the selected match's group.
  if (readout_.group && readout_.inspector && !model_.playing && !group_series_asked_ && readout_.at.latest >= 0 &&
      std::ranges::count(readout_.group->modules, readout_.inspector->module) > 0 &&
      !(group_series_ && group_series_->holds(readout_.group->modules, readout_.inspector->plot_column,
                                              readout_.at.latest, readout_.interventions.size()))) {
    group_series_asked_ = true;
    worker_->submit(
        [this, modules = readout_.group->modules, column = readout_.inspector->plot_column](
            sim::Session& s, const sim::Control& control) {
          auto series = read_group_series(s, modules, column, ReadoutLimits{}.plot_steps, control);
          if (series) group_series_ = std::move(*series);
          group_series_asked_ = false;
        },
        /*background=*/true);
  }
}

void Debugger::play() {
  if (!model_.playing) play_clock_started_ = false;
  if (!model_.playing || suspend_play_ || !worker_->idle() || readout_stale_ || readout_.version != worker_->finished())
    return;
  const auto now = std::chrono::steady_clock::now();
  if (!play_clock_started_) {  // play's clock starts with play: a `run 60` before it is not its time
    play_clock_started_ = true;
    last_request_ = now;
    return;
  }
  const double since = std::chrono::duration<double>(now - last_request_).count();
  const int64_t last = readout_.at.end > 0 ? readout_.at.end - 1 : INT64_MAX;
  if (readout_.at.current >= last) {
    model_.playing = false;
    status("the scenario's end (step " + std::to_string(last) + "): step on with -> or `run` past it");
    return;
  }
  int64_t n;
  if (model_.speed <= 0) {
    // As many steps a request as take about kFastRequestSeconds, from what the last playing
    // request took a step (play only asks when the worker is idle, so the last job was it).
    if (fast_asked_ > 0 && last_job_seconds_ > 0) {
      const double per_step = last_job_seconds_ / double(fast_asked_);
      fast_steps_ = std::clamp<int64_t>(int64_t(kFastRequestSeconds / per_step), 1, 1000);
    }
    n = fast_steps_;
  } else {
    n = model_.steps_due(since);
    if (n < 1) return;
  }
  n = std::min(n, last - readout_.at.current);
  fast_asked_ = model_.speed <= 0 ? n : 0;
  send(command::step(n));
  last_request_ = now;
}

}  // namespace dw::view
