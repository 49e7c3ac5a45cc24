// Bearer tokens and caller identities (access.h).
#include <lixel/service/access.h>

#include <lixel/service/client_limits.h>

#include <openssl/crypto.h>
#include <openssl/sha.h>

#include <array>
#include <optional>
#include <cctype>

namespace lixel::service {

namespace {

using Digest = std::array<unsigned char, SHA256_DIGEST_LENGTH>;

Digest Sha256(std::string_view text) {
    Digest digest{};
    SHA256(reinterpret_cast<const unsigned char*>(text.data()), text.size(), digest.data());
    return digest;
}

bool SameDigest(const Digest& a, const Digest& b) {
    return CRYPTO_memcmp(a.data(), b.data(), a.size()) == 0;
}

std::string_view Trim(std::string_view s) {
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
    return s;
}

// The token of an "authorization: Bearer <token>" header, or nullopt.
std::optional<std::string_view> PresentedToken(const grpc::CallbackServerContext& context) {
    const auto& metadata = context.client_metadata();
    const auto it = metadata.find("authorization");
    if (it == metadata.end()) return std::nullopt;
    const std::string_view value(it->second.data(), it->second.size());
    constexpr std::string_view kScheme = "Bearer ";
    if (value.substr(0, kScheme.size()) != kScheme) return std::nullopt;
    return value.substr(kScheme.size());
}

// The subject of a verified client certificate (mutual TLS), or empty.
std::string CertificateSubject(const grpc::CallbackServerContext& context) {
    const auto auth = context.auth_context();
    if (auth == nullptr || !auth->IsPeerAuthenticated()) return {};
    const auto identity = auth->GetPeerIdentity();
    if (identity.empty()) return {};
    return std::string(identity.front().data(), identity.front().size());
}

}  // namespace

Result<std::map<std::string, std::string>> ParseClientTokens(std::string_view text) {
    std::map<std::string, std::string> tokens;
    int line_number = 0;
    while (!text.empty()) {
        const auto end = text.find('\n');
        const std::string_view line = Trim(text.substr(0, end));
        text = end == std::string_view::npos ? std::string_view() : text.substr(end + 1);
        ++line_number;
        if (line.empty() || line.front() == '#') continue;
        const std::string field = "clients_file:" + std::to_string(line_number);
        std::size_t split = 0;
        while (split < line.size() && !std::isspace(static_cast<unsigned char>(line[split]))) {
            ++split;
        }
        const std::string_view name = line.substr(0, split);
        const std::string_view token = Trim(line.substr(split));
        if (token.empty()) return Error{field, "needs a name and a token"};
        for (const char c : token) {
            if (std::isspace(static_cast<unsigned char>(c)) || !std::isprint(static_cast<unsigned char>(c))) {
                return Error{field, "the token has a space or an unprintable character"};
            }
        }
        // A short token can be guessed; 16 characters of a random hex string are 64 bits.
        if (token.size() < 16) return Error{field, "the token is shorter than 16 characters"};
        if (!tokens.emplace(std::string(token), std::string(name)).second) {
            return Error{field, "the token is already given to client '" +
                                    tokens.at(std::string(token)) + "'"};
        }
    }
    return tokens;
}

grpc::Status IdentifyCaller(const grpc::CallbackServerContext& context,
                            const ServiceOptions& options, std::string* identity) {
    std::string client_name;
    if (!options.bearer_token.empty() || !options.client_tokens.empty()) {
        const auto presented = PresentedToken(context);
        const Digest digest = Sha256(presented.value_or(std::string_view()));
        bool accepted = false;
        // Every token is compared, matched or not, so the time taken does not depend on which.
        if (!options.bearer_token.empty() && SameDigest(digest, Sha256(options.bearer_token))) {
            accepted = true;
        }
        for (const auto& [token, name] : options.client_tokens) {
            if (SameDigest(digest, Sha256(token))) {
                accepted = true;
                client_name = name;
            }
        }
        if (!presented || !accepted) {
            return grpc::Status(grpc::StatusCode::UNAUTHENTICATED,
                                "authorization: missing or wrong bearer token");
        }
    }
    if (!client_name.empty()) {
        *identity = "client:" + client_name;
    } else if (std::string subject = CertificateSubject(context); !subject.empty()) {
        *identity = "cert:" + subject;
    } else {
        *identity = ClientLimits::PeerHost(context.peer());
    }
    return grpc::Status::OK;
}

}  // namespace lixel::service
