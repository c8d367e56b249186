#include "cli/app.h"

#include "cli/commands.h"
#include "cli/options.h"

namespace facerig::cli {

void AddCommands(CLI::App& app, CommandBody& body) {
  AddInspectCommand(app, body);
  AddConvertCommand(app, body);
  AddLandmarksCommand(app, body);
  AddRegisterCommand(app, body);
  AddBuildCommand(app, body);
  AddPhotoCommand(app, body);
  AddAverageCommand(app, body);
  AddCaricatureCommand(app, body);
  AddMorphCommand(app, body);
  AddDefaultHeadCommand(app, body);
#ifdef FACERIG_CLI_ALIGN
  AddAlignCommand(app, body);
#endif
}

int RunFacerig(int argc, char** argv) {
  CLI::App app("facerig: inspect, convert and build blend-shape rigs", "facerig");
  AddVersionFlag(app);
  CommandBody body;
  AddCommands(app, body);
  app.footer("Run 'facerig COMMAND --help' for a command's options. Exit codes: 0 ok, 1 failure, 2 bad command line.");
  if (const std::optional<int> exit_code = ParseSubcommandLine(app, argc, argv)) return *exit_code;
  return body();
}

}  // namespace facerig::cli
