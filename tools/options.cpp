// The options several subcommands share (commands.hpp).
#include "commands.hpp"

namespace acuity::tools {

void add_chain_options(CLI::App* cmd, bake::BakeOptions& b) {
  cmd->add_option("--levels", b.levels, "Number of levels (0: halve down to ~1%; at most 32)")
      ->capture_default_str()
      ->check(CLI::Range(0, 32));
  add_number(cmd, "--ratio", b.ratio, "Triangles of each level over the previous", 0.01, 0.99);
  add_number(cmd, "--max-error", b.max_error, "Stop at this Hausdorff error [bounding-sphere diameters]", 0,
             1e6);
  cmd->add_option(
         "--backend", b.backend,
         "meshopt (keeps creases and seams) | openmesh | cgal (Garland-Heckbert) | cgal-lt (Lindstrom-Turk)")
      ->capture_default_str();
  cmd->add_flag("--lock-border", b.lock_border, "Keep border vertices in place");
  add_number(cmd, "--crease", b.crease, "Edges sharper than this are drawn sharp [degrees]; 180: all smooth",
             0, 180);
  add_number(cmd, "--measure-seconds", b.measure_seconds,
             "Time budget for measuring an asset's errors; past it errors are lower bounds (a warning)", 0.1,
             1e5);
  add_number(cmd, "--reference-height", b.reference_height, "Pixels, for MSFT_screencoverage", 1, 1e6);
  cmd->add_option("--asset-root", b.asset_root,
                  "Folder a glTF's uris may read from (default: the glTF's own folder)");
}

void add_profile_options(CLI::App* cmd, bake::BakeOptions& b) {
  add_number(cmd, "--res", b.pixels, "Snapshot pixels across the object (power of two)", 16, 4096);
  add_number(cmd, "--orientations", b.orientations, "Orientations over 180 deg", 1, 32);
  add_number(cmd, "--bands", b.bands, "Number of octave bands (0: all up to res / 4)", 0, 32);
  add_number(cmd, "--tolerance", b.tolerance, "Adaptive views: switching-distance error allowed", 0, 1e6);
  cmd->add_flag("!--no-cell-bounds", b.bound_cells,
                "Store each view's own measurement, not the largest loss over its cell (faster, optimistic "
                "between views)");
  add_number(cmd, "--window-pixels", b.window_pixels,
             "Cluster hierarchies: pixels across each group's window (power of two)", 16, 4096);
  cmd->add_option("--group-views", b.group_views, "Cluster hierarchies: directions measured per group")
      ->capture_default_str()
      ->check(CLI::IsMember({12, 42, 162}));
  cmd->add_flag("--view-cells", b.view_cells,
                "Cluster hierarchies: also store each group's loss per view cell (the ClusterViews section, "
                "about 337 bytes per group) when measured from fewer than 162 directions, where the runtime "
                "does not read it");
}

namespace {
// An option naming one value of an enum (`noun`: "model"), checked at parse time by the library's
// own parser, its names in the help and the error, its default printed by the library's to_string.
template <class Enum>
void add_named_option(CLI::App* cmd, const std::string& flag, Enum& value, const std::string& help,
                      const char* noun, bool (*parse)(const char*, Enum*), const std::string& names) {
  const CLI::Validator name(
      [parse, noun, names](std::string& text) -> std::string {
        Enum v{};
        if (!parse(text.c_str(), &v))
          return std::string("unknown ") + noun + " '" + text + "' (" + names + ")";
        text = std::to_string(int(v));  // the enum's value, which CLI11 then reads
        return {};
      },
      "");
  cmd->add_option(flag, value, help + ": " + names)
      ->transform(name)
      ->type_name("NAME")
      ->default_str(to_string(value));
}
}  // namespace

void add_model_option(CLI::App* cmd, ThresholdModel& model, const std::string& what) {
  add_named_option(cmd, "--model", model, what, "model", parse_threshold_model, threshold_model_names());
}

void add_evaluation_option(CLI::App* cmd, Evaluation& evaluation, const std::string& what) {
  const std::string names =
      std::string(to_string(Evaluation::Tabulated)) + ", " + to_string(Evaluation::Exact);
  add_named_option(cmd, "--evaluation", evaluation, what, "evaluation", parse_evaluation, names);
}

}  // namespace acuity::tools
