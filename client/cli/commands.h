// The lixel CLI's commands. Each prints errors as the server gave them and returns an exit code.
#pragma once

#include "cli_options.h"

namespace lixel::cli {

int UploadCommand(client::Client& client, const Flags& flags);
int SolveCommand(client::Client& client, const Flags& flags);
int PlanCommand(client::Client& client, const Flags& flags);
int RenderCommand(client::Client& client, const Flags& flags);
int ViewCommand(client::Client& client, const Flags& flags);
int ReportCommand(client::Client& client, const Flags& flags);

int Fail(const Error& error);

}  // namespace lixel::cli
