// Who a call comes from: bearer-token authorisation, and the identity the per-client limits
// (client_limits.h) count it under.
#pragma once

#include <lixel/service/service_options.h>
#include <lixel/solver/result.h>

#include <grpcpp/grpcpp.h>

#include <map>
#include <string>
#include <string_view>

namespace lixel::service {

// A clients file (lixel_server --clients_file): one "<name> <token>" per line, separated by
// spaces or tabs; blank lines and lines starting with '#' are skipped. Returns token -> name.
// Errors name the line: field "clients_file:3", reason "needs a name and a token".
Result<std::map<std::string, std::string>> ParseClientTokens(std::string_view text);

// Authorises a call and names it. When the server checks tokens (options.bearer_token or
// options.client_tokens set), the call must carry "authorization: Bearer <token>" with one of
// them, else UNAUTHENTICATED; tokens are compared by SHA-256 digest in constant time, every one
// of them, so the time taken tells nothing of how close a guess came. The identity is, first
// that applies: "client:<name>" for a token from client_tokens; "cert:<subject>" for a client
// that presented a verified certificate (mutual TLS); the host part of the peer address
// ("ipv4:127.0.0.1"). The shared bearer_token authorises but does not identify: its holders are
// told apart by certificate or address.
grpc::Status IdentifyCaller(const grpc::CallbackServerContext& context,
                            const ServiceOptions& options, std::string* identity);

}  // namespace lixel::service
