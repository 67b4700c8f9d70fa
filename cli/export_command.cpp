#include "cli/export_command.hpp"

#include "cli/console.hpp"
#include "cli/directory_option.hpp"

namespace demcal::cli {

CLI::App* add_export_command(CLI::App& app, ExportOptions& o) {
  CLI::App* cmd = app.add_subcommand(
      "export", "Write the calibrated material card for another engine (after calibrate)");
  cmd->add_option("study", o.card.study, "The study config (TOML)")->required();
  cmd->add_option("--to", o.card.to, "Card format")
      ->required()
      ->check(CLI::IsMember({"liggghts", "lammps", "edem-csv", "json"}));
  cmd->add_option("--set", o.card.overrides, "Override a config value, as for doe (repeatable)");
  cmd->add_option("--output", o.card.output_dir,
                  "Output directory of the study's runs (default out)")
      ->check(directory_to_write());
  cmd->add_option("--card", o.card_file,
                  "Where to write the card (default <output>/<study>/material/<study>.<to>.<ext>)");
  return cmd;
}

int run_export(ExportOptions& o, std::ostream& out, std::ostream& log) {
  if (!o.card_file.empty()) o.card.card = o.card_file;
  const study::MaterialExportOutcome r = study::export_material_card(o.card);
  for (const std::string& w : r.warnings) warn_once(log, w);
  out << "material card: " << r.card.string() << "\n";
  return 0;
}

}  // namespace demcal::cli
