// A scenario's [[event]] tables: interventions scheduled at the start of a step (docs/design.md
// §7), read once the model is built, since they name its modules and variables; and its
// [[bookmark]] tables, notes on steps.
#include "scenarios/scenario_loader.h"

namespace dw::scenarios {

// [[event]]: at, module, and one of set = { var = value, ... }, remove = true, push = [x, y, z].
std::vector<sim::Intervention> Loader::events(const std::vector<const toml::table*>& tables, const sim::Model& model,
                                              bool physics) {
  std::vector<sim::Intervention> out;
  for (const toml::table* t : tables) {
    TableReader r(*t, diagnostics, "[[event]]");
    const auto at = r.integer("at", 0, kStepsRange.max);
    const auto module = r.integer("module", 0, int64_t{model.module_count()} - 1);
    if (!r.has("at")) r.missing("at");
    if (!r.has("module")) r.missing("module");
    const int kinds = int(r.has("set")) + int(r.has("remove")) + int(r.has("push"));
    if (kinds == 0) {
      diagnostics.add(t->source(), "[[event]] needs one of 'set', 'remove' or 'push'");
      r.finish();
      continue;
    }
    if (kinds > 1) {
      r.error(r.has("push") ? "push" : "remove", "an event does one thing: 'set', 'remove' or 'push'");
      for (const char* key : {"set", "remove", "push"}) r.node(key);
      r.finish();
      continue;
    }
    sim::Intervention base;
    base.at = at.value_or(0);
    base.module = static_cast<sim::ModuleId>(module.value_or(0));
    base.scheduled = true;
    const auto kind = r.has("set")      ? sim::Intervention::Kind::Set
                      : r.has("remove") ? sim::Intervention::Kind::Remove
                                        : sim::Intervention::Kind::Push;
    const std::string empty = module ? sim::empty_cell_problem(model.lattice, base.module, kind) : "";
    if (!empty.empty()) r.error("module", empty);
    const bool ok = at && module && empty.empty();
    if (const toml::table* set = r.has("set") ? r.table("set") : nullptr) {
      if (set->empty()) r.error("set", "'set' names no variable: set = { var = value }");
      for (const auto& [key, value] : *set) {
        const int column = model.column(key.str());
        if (column < 0) {
          diagnostics.add(key.source(), "no program has a variable named \"" + std::string(key.str()) + "\"");
        } else if (!value.is_integer()) {
          diagnostics.add(value.source(), "'" + std::string(key.str()) + "' must be set to an integer");
        } else if (ok) {
          sim::Intervention i = base;
          i.kind = sim::Intervention::Kind::Set;
          i.column = column;
          i.value = value.as_integer()->get();
          out.push_back(i);
        }
      }
    }
    if (r.has("remove")) {
      const auto remove = r.boolean("remove");
      if (remove && !*remove) r.error("remove", "'remove' takes true (leave the key out for no removal)");
      else if (remove && ok)
        out.push_back(
            {.kind = sim::Intervention::Kind::Remove, .at = base.at, .module = base.module, .scheduled = true});
    }
    if (r.has("push")) {
      const auto push = r.numbers("push", 3, -1e9, 1e9);
      if (push && !physics) r.error("push", "a push needs bodies: this scenario has no [physics]");
      else if (push && ok) {
        sim::Intervention i = base;
        i.kind = sim::Intervention::Kind::Push;
        i.impulse = {float((*push)[0]), float((*push)[1]), float((*push)[2])};
        out.push_back(i);
      }
    }
    r.finish();
  }
  return out;
}

// [[bookmark]]: at, note (a line of text).
std::vector<sim::Bookmark> Loader::bookmarks(const std::vector<const toml::table*>& tables) {
  std::vector<sim::Bookmark> out;
  for (const toml::table* t : tables) {
    TableReader r(*t, diagnostics, "[[bookmark]]");
    const auto at = r.integer("at", 0, kStepsRange.max);
    const auto note = r.string("note");
    if (!r.has("at")) r.missing("at");
    if (note && note->find('\n') != std::string::npos) r.error("note", "a bookmark's note is one line");
    else if (at) out.push_back({*at, note.value_or("")});
    r.finish();
  }
  return out;
}

}  // namespace dw::scenarios
