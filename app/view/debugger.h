// `dwatch view`: the debugger window (GLFW + Dear ImGui) over one session. The 3D view (the same
// renderer and scene as `dwatch render`), the transport bar and a timeline of every watchpoint's
// matches, and panels for the watchpoints, the matches, the selected module, interventions and
// statistics. Every widget sends a line of the session language (docs/design.md §7a) through the same
// shell::Shell as `dwatch session`, run by a worker thread so that the window keeps drawing; what
// the panels show is a Readout read between jobs. A script drives the same window: the session's
// commands, plus `click`, `key`, `wait`, `screenshot` and `panel`.
#pragma once

#include <array>
#include <atomic>
#include <chrono>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <imgui.h>
#include "shell/shell.h"

#include "app/view/glfw_window.h"
#include "app/view/readout.h"
#include "app/view/session_worker.h"
#include "app/view/view_model.h"
#include "app/view/why_diagram.h"
#include "app/view/widgets.h"
#include "render/image.h"
#include "render/renderer.h"
#include "render/video_writer.h"

namespace dw::view {

// The window's settings file: $XDG_CONFIG_HOME/dwatch/view.ini (or ~/.config/...), never the
// repository; empty when neither is set.
std::string layout_file();

// The module whose id (as answers give it) is `id`: itself, unless the model has a trace's ids.
std::optional<sim::ModuleId> module_of_id(const watch::Universe& universe, uint32_t id);

// A vector as X,Y,Z text, as --camera-eye takes it.
std::string vec_text(glm::vec3 v);

// Where a widget a script may press or type into was drawn in the last frame (window pixels).
struct WidgetPlace {
  float x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  bool cut = false;           // wider than its panel or cell shows, or its text wider than it
  bool out_of_sight = false;  // above or below its panel's visible area: scrolled away
  bool disabled = false;      // drawn greyed out: a press does nothing
  float text_width = 0;       // its text's, when it has one to show whole (a table's header)
};

class Debugger {
 public:
  // `layout`: where ImGui keeps the panels' places between runs; empty: not kept.
  Debugger(const scenarios::Scenario& scenario, sim::Session& session, GlfwWindow& window, std::string layout);
  ~Debugger();
  Debugger(const Debugger&) = delete;
  Debugger& operator=(const Debugger&) = delete;

  // Until the window is closed.
  int run_interactive();
  // Every line checked first (a mistake: exit 2), then carried out, each answered with one JSON
  // line on stdout; a command that fails stops the script (exit 1).
  int run_script(const watch::SourceText& script);

  // One frame: input, a fresh Readout if the session changed, panels, the 3D view, swap.
  void frame();
  // Frames until the worker has nothing left to do and the Readout is current.
  void settle();

  ViewModel& model() { return model_; }
  const Readout& shown() const { return readout_; }
  SessionWorker& worker() { return *worker_; }
  // Sends a line of the session language to the worker; its answer (or mistake) comes back
  // through the status line, and to a script.
  void send(const std::string& line);

 private:
  struct Answer {
    std::string line;
    std::string error;  // empty: `json` holds the answer
    nlohmann::ordered_json json;
  };
  struct ViewArea {
    float x = 0, y = 0;  // the 3D view's top-left corner in the window, in framebuffer pixels
    int width = 0, height = 0;
  };

  // debugger.cpp: the lifecycle and the frame loop
  bool settled();

  // session_link.cpp: what the window sends the session and reads back
  // Answers first (to the status line), then a fresh Readout when the session changed.
  void refresh_readout();
  void ask_for_history();
  void apply(const std::vector<std::string>& commands);
  void status(std::string message, bool failed = false);  // `failed`: shown in red
  void play();

  // keyboard.cpp
  void handle_keys();
  void press(Key key);

  // camera.cpp
  render::Scene& camera_scene();  // the Readout's scene, seen through the user's camera
  void place_camera();
  void focus_on_selection();
  void reveal_group();
  // How many of `modules` (every module when empty) show inside the 3D view.
  int modules_in_view(std::span<const sim::ModuleId> modules);
  // The mouse over the 3D view (its invisible button the last item) turns, pans and zooms the
  // camera; true when the left button was let go without a drag: a click.
  bool steer_camera(bool hovered);

  // edge_pointers.cpp
  void follow_module();  // the camera's target on the followed module
  // Pointers at the 3D view's edge towards the modules out of it that matter (window pixels from
  // the view's top left; `scale`: framebuffer per window pixel), found again when what shows changed.
  void find_edge_pointers(ImVec2 scale);
  void draw_edge_pointers(ImVec2 origin, ImVec2 scale);

  // picking.cpp
  // The mouse at framebuffer pixel (x, y) of the 3D view: the camera's drags, a click selects, a
  // hover names the module.
  void view_input(float x, float y, bool hovered);
  std::optional<sim::ModuleId> module_at(float x, float y);
  // Where the module with this id (as answers give it) shows over the 3D view, whose picture's top
  // left is at `origin` (window pixels; `scale`: framebuffer per window pixel); nothing off screen.
  std::optional<ImVec2> module_on_screen(uint32_t id, const glm::mat4& vp, ImVec2 origin, ImVec2 scale) const;

  // layout.cpp
  // Tiles the window for this frame (panels_), and decides whether the panels go there (panels_cond_).
  void lay_out_panels();
  // The next window goes where panels_ puts `rect` (see panels_cond_).
  void place(const PanelRect& rect) const;

  // scene_view.cpp
  void draw_view();
  void cut_tools();  // the 3D view's tool row: the cut plane's axis and place
  void render_view_texture(bool moving);
  std::string screenshot_view(const std::string& path);

  // compose.cpp
  // Puts the 3D view and the panels together in composed_fbo_, redrawing only what changed; false
  // when nothing did (the window keeps what it shows).
  bool compose(int width, int height);

  // window_script.cpp
  nlohmann::ordered_json window_command(const std::vector<std::string>& words, std::string& error);
  // A line of the session language, sent as the panels send theirs, and its answer once settled.
  nlohmann::ordered_json session_command(const std::string& line, std::string& error);
  // Each adds to `answer`, or says in `error` why the command could not be carried out.
  void input_command(const std::vector<std::string>& words, nlohmann::ordered_json& answer, std::string& error);
  void screenshot_command(const std::vector<std::string>& words, nlohmann::ordered_json& answer, std::string& error);
  void press_command(const std::vector<std::string>& words, nlohmann::ordered_json& answer, std::string& error);
  void panel_command(const std::vector<std::string>& words, nlohmann::ordered_json& answer, std::string& error);
  // screencast.cpp: `screencast FILE | stop`; film_window adds the window as it stands now as the
  // next `frames` frames (an error ends the screencast); finish_screencast puts the video in place.
  void screencast_command(const std::vector<std::string>& words, nlohmann::ordered_json& answer, std::string& error);
  std::string film_window(int64_t frames);
  std::string finish_screencast();
  // A press of the left button at window pixel (x, y), and its release, through GLFW's callbacks as
  // the platform delivers them: what ImGui draws there reacts as to a person's click. False when
  // the pointer cannot get there (off the screen).
  bool click_at(float x, float y);
  // Keys and characters typed into the active text field, through the same path.
  void type_text(const std::string& text);

  // recording.cpp
  void start_recording(const std::string& path);
  void record_frame();  // when a new step shows
  void stop_recording();

  // widgets.cpp
  // Notes the last widget under `name` (its label before any "##") for `press` and `type`;
  // `text_width`: the width of what it shows, when that may be wider than the widget (a combo's
  // choice), so that a cut label is found; `selectable`: an item of a list.
  void note_widget(const std::string& name, float text_width = 0, bool selectable = false);
  bool button(const std::string& label, bool small = false);  // ImGui::Button, noted
  // A combo of `items`, noted as `name`, its open list's items as "NAME: ITEM".
  void choice(const std::string& name, int& chosen, std::span<const char* const> items);
  // A name in a table cell (a watchpoint's): whole, or cut with "..." (whole in a tooltip) and
  // noted, for the tests that look for cut labels.
  void label_cell(const std::string& text, std::optional<ImVec4> color = std::nullopt);
  // ImGui::TableHeadersRow, noting each header as a widget "TABLE: NAME" (where its text shows)
  // and each that does not show whole among the cut labels.
  void headers_row(const std::string& table);
  // panels.cpp
  void draw_panels();
  void transport_panel();
  void watchpoints_panel();
  void editor();
  void matches_panel();
  void save_matches();  // the Matches panel's "save the matches"
  // timeline.cpp
  void timeline(float width);
  void timeline_scale(float y);  // the steps written under the timeline's lanes
  // module_panels.cpp
  void inspector_panel();
  void variables_table(const Inspector& in);
  void interventions_row(const Inspector& in);
  void session_files_row();
  void statistics_panel();
  void statistics_tab();
  // group_panel.cpp: the Group tab beside the statistics (the selected match's group side by side,
  // pinned conditions, and searching back and on for where they hold)
  void group_tab();
  void pins_rows(const GroupTable& g);
  // marks_panel.cpp: the marks and diff tabs, and the diff's modules ringed over the 3D view
  void marks_tab();
  const sim::Bookmark* timeline_bookmarks(float top, float height);
  void diff_tab();
  void diff_in_view(ImVec2 origin, ImVec2 scale);
  void help_window();
  // why_panel.cpp: the Why panel, the session's `why` answer drawn as a space-time diagram, and the
  // cone's marks in the 3D view
  void show_why(const nlohmann::ordered_json& answer, const std::string& line);  // a `why` answered
  // Sends `why ...` (its options taken off) with the panel's depth and narrowness.
  void ask_why(const std::string& line);
  void why_last_changed();  // Y: the selected module's variable that changed last
  void why_panel();
  void why_diagram_canvas(const WhyDiagram& d);
  // The cone's modules lit at the current step and the messages read at it as arrows, over the 3D
  // view whose picture's top left is at `origin` (window pixels; `scale`: framebuffer per window).
  void why_in_view(ImVec2 origin, ImVec2 scale);

  const scenarios::Scenario& scenario_;
  sim::Session& session_;
  GlfwWindow& window_;
  std::string layout_;
  shell::Shell shell_;
  std::unique_ptr<SessionWorker> worker_;
  std::unique_ptr<render::Renderer> renderer_;
  ViewModel model_;
  Readout readout_;
  bool readout_stale_ = true;
  std::optional<sim::ProgramFailure> shown_failure_;  // the Readout's, when last read

  // The inspector's history of the selected module, written by a worker job (under the session's
  // lock, as is every read of it).
  std::optional<ModuleWindow> module_window_;
  std::atomic<bool> module_window_asked_ = false;
  // The Group tab's step before and pins, written by a worker job as module_window_ is.
  std::optional<GroupWindow> group_window_;
  std::atomic<bool> group_window_asked_ = false;
  // The Module plot's other lines (the selected match's group), written by a worker job too.
  std::optional<GroupSeries> group_series_;
  std::atomic<bool> group_series_asked_ = false;
  char pin_text_[256] = "";  // the Group tab's field for a new pin
  std::string pin_error_;    // why the last pin was not taken
  // The Statistics panel shows its group, marks or diff tab (set as it draws), and did so when the
  // panels were last laid out.
  bool tall_tabs_ = false, panels_tall_tabs_ = false;
  char mark_note_[256] = "";                    // the marks tab's note for the next bookmark
  int diff_step_ = 0;                           // the diff tab's other step
  std::optional<nlohmann::ordered_json> diff_;  // the last `diff` answered

  std::mutex answers_mutex_;
  std::vector<Answer> answers_;  // from the worker, in order
  size_t answers_seen_ = 0;      // by the status line
  std::string status_;           // the last answer or mistake, in the transport bar
  bool status_failed_ = false;   // a mistake: in red
  std::string paused_on_;        // the pause watchpoint that stopped the cursor, while it stands there

  // The 3D view: a texture the renderer draws into, redrawn when what it shows changes.
  ViewArea view_;
  unsigned view_fbo_ = 0, view_texture_ = 0;
  int texture_width_ = 0, texture_height_ = 0;
  std::string drawn_key_;  // what the texture shows
  // While the camera moves or the session plays, the view is drawn at a lower resolution (a
  // software rasteriser's cost grows with the pixels) and again in full once it holds still.
  static constexpr float kMotionScale = 0.35f;
  int drawn_width_ = 0, drawn_height_ = 0;
  glm::vec3 last_eye_{0}, last_target_{0};
  uint64_t last_version_ = 0;
  // The window's picture, kept between frames: the panels are rasterised again only when ImGui's
  // drawing changed, the 3D view copied in only when it was drawn again.
  unsigned composed_fbo_ = 0, composed_color_ = 0;
  int composed_width_ = 0, composed_height_ = 0;
  uint64_t composed_ui_hash_ = 0;
  std::string composed_view_key_;
  int timeline_columns_ = 0;  // the timeline's width in pixels as last drawn
  std::chrono::steady_clock::time_point rows_read_at_;
  std::string rows_key_;  // what the matches table's rows were read for
  std::optional<sim::ModuleId> hovered_;
  struct EdgePointerMark {
    glm::vec2 at, toward;  // the tip, from the 3D view's top left (window pixels); outwards
    ImU32 color;
    int64_t module;  // its id
    int more;        // modules out of the view on nearly the same line, drawn as one
  };
  std::vector<EdgePointerMark> pointers_;
  std::string pointers_key_;  // what they were found for
  bool dragging_ = false;
  std::string window_shot_, window_shot_error_;  // a script's `screenshot`, taken after the next frame
  // Where the panels go (view_model.h): the first time from the layout file if there is one, and
  // again, for every panel, whenever the window's size changes.
  PanelLayout panels_;
  int panels_cond_ = 0;  // ImGuiCond_Always after a resize, else ImGuiCond_FirstUseEver
  float panels_width_ = 0, panels_height_ = 0;
  int panels_lanes_ = 0;
  Timeline timeline_;                           // as last drawn
  float timeline_y_ = 0, timeline_height_ = 0;  // its lanes' top and height in the window

  // Playing.
  std::chrono::steady_clock::time_point last_request_;
  int64_t fast_steps_ = 1;  // steps per request when playing as fast as possible
  int64_t fast_asked_ = 0;  // steps of the last such request
  std::atomic<double> last_job_seconds_ = 0;
  bool suspend_play_ = false;        // while a script waits for the session to settle
  bool play_clock_started_ = false;  // last_request_ counts from when play started, not before

  // The editor.
  std::string edit_name_ = "w1", edit_text_;
  int edit_algorithm_ = 1, edit_action_ = 0;  // distributed, log
  int edit_shape_ = 0, edit_states_ = 0;      // chain, consistent: the paper's distributed reading
  std::string edit_checked_;                  // the name and text last compiled
  std::string edit_diagnostics_, edit_explanation_;
  // The editor's text and its diagnostics in a monospace font: the caret line is aligned with
  // spaces, which in a proportional font put column 39 under another word. Null: none installed.
  ImFont* mono_font_ = nullptr;
  bool edit_ok_ = false;

  // Interventions and files.
  // Watchpoints switched off: out of the session (they watch nothing), their definitions kept
  // here, so that switching one on evaluates it over the history again.
  struct DisabledWatch {
    std::string name, options, text;
  };
  std::vector<DisabledWatch> disabled_;
  int set_column_ = 0;
  char record_path_[256] = "trace.jsonl", matches_path_[256] = "matches.jsonl";
  // The Why panel: the diagram of the last `why` answered, how it is scrolled, the options the
  // next ask sends, and where the last frame drew it (`panel why`).
  std::optional<WhyDiagram> why_;
  WhyView why_view_;
  bool why_open_ = false, why_narrow_ = true, panels_why_ = false;
  int why_depth_ = 3;
  std::string why_asked_;  // the last `why` line without its options
  nlohmann::ordered_json why_drawn_;
  std::vector<std::array<float, 4>> plot_rects_;              // the last frame's plots: x0, y0, x1, y1
  std::vector<PlotLabel> plot_labels_;                        // the texts its Module plot wrote
  std::map<std::string, WidgetPlace> widgets_;                // the last frame's buttons and fields, by name
  std::map<std::string, WidgetPlace> drawing_widgets_;        // this frame's, as they are drawn
  std::vector<std::string> cut_labels_, drawing_cut_labels_;  // the last frame's / this frame's
  std::string scroll_to_;     // a widget out of sight that `press` scrolls its panel to, as a person would
  char save_path_[256] = "";  // "Save as scenario": where (`save FILE`)
  std::string save_sent_;     // the file of the last `save` sent
  std::string save_refused_;  // the file a `save` would have overwritten, asking to confirm
  int64_t set_value_ = 0;
  float push_[3] = {0, 0, 5};
  int goto_step_ = 0;
  int filter_module_ = -1;

  // The Record button's video, while it records.
  std::unique_ptr<render::VideoWriter> video_;
  render::VideoSettings video_settings_;
  // A window script's screencast of the whole window (screencast.cpp).
  std::unique_ptr<render::VideoWriter> screencast_;
  render::VideoSettings screencast_settings_;
  int64_t video_step_ = -1;  // the step last recorded
  char video_path_[256] = "";

  double frame_seconds_ = 0;  // the last frame's time
  // What the statistics panel shows of it, updated twice a second (a number changing every frame
  // would make every frame redraw the panels).
  double shown_frame_ms_ = 0;
  std::chrono::steady_clock::time_point frame_time_shown_at_;
};

}  // namespace dw::view
