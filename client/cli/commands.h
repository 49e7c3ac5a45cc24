// The lixel CLI's commands. Each prints errors as the server gave them and returns an exit code.
#pragma once

#include "cli_options.h"

namespace lixel::cli {

// The flags a command takes besides the connection flags; null for an unknown command.
const std::set<std::string>* CommandFlags(const std::string& command);

int UploadCommand(client::Client& client, const Flags& flags);
int SolveCommand(client::Client& client, const Flags& flags);
int PlanCommand(client::Client& client, const Flags& flags);
int RenderCommand(client::Client& client, const Flags& flags);
int ViewCommand(client::Client& client, const Flags& flags);
int ReportCommand(client::Client& client, const Flags& flags);
int SequenceCommand(client::Client& client, const Flags& flags);
int FramesCommand(client::Client& client, const Flags& flags);

// A failed call or file: prints the error, returns 1.
int Fail(const Error& error);
// A mistake on the command line (a flag or its value): prints the error, returns 2.
int UsageError(const Error& error);

}  // namespace lixel::cli
