// lixel report: the error-vs-run-time sweep over the service (placeholder replaced below).
#include "commands.h"

namespace lixel::cli {

int ReportCommand(client::Client& client, const Flags& flags) {
    (void)client;
    (void)flags;
    return Fail(Error{"report", "not built yet"});
}

}  // namespace lixel::cli
