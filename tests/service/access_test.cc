// Tests for who a call comes from (lixel/service/access.h): the clients file, bearer tokens
// shared or per client, and the identity the per-client limits count: a client's own token
// name, its mutual-TLS certificate subject, or its address.
#include <lixel/service/access.h>
#include <lixel/service/client_limits.h>

#include <algorithm>

#include "service_fixture.h"
#include "test_ca.h"

namespace lixel {
namespace {

using service::ClientLimits;
using service::ParseClientTokens;
using testing::BigRender;
using testing::CallSolve;
using testing::Connect;
using testing::Eventually;
using testing::RawStub;
using testing::SmallScene;
using testing::SmallServerOptions;
using testing::SmallSolve;
using testing::StartServer;
using testing::Target;
using testing::TestCa;
using testing::WithDeadline;

constexpr const char* kLoopback = "ipv4:127.0.0.1";
constexpr const char* kAlphaToken = "alpha-5f1c0a9e7d3b2468";
constexpr const char* kBetaToken = "beta-0d9e8c7b6a594837";

TEST(ClientTokens, ParsesNamesAndTokensSkippingCommentsAndBlankLines) {
    auto tokens = ParseClientTokens(
        "# lixel clients\n\nalpha alpha-5f1c0a9e7d3b2468\n  beta\t beta-0d9e8c7b6a594837  \r\n");
    ASSERT_TRUE(tokens.ok()) << tokens.error().Message();
    ASSERT_EQ(tokens->size(), 2u);
    EXPECT_EQ(tokens->at(kAlphaToken), "alpha");
    EXPECT_EQ(tokens->at(kBetaToken), "beta");
    EXPECT_TRUE(ParseClientTokens("").ok());
}

TEST(ClientTokens, BadLinesAreRefusedNamingTheLine) {
    struct Case {
        const char* text;
        const char* field;
        const char* reason;
    };
    const Case cases[] = {
        {"alpha\n", "clients_file:1", "needs a name and a token"},
        {"# one\nalpha short\n", "clients_file:2", "shorter than 16"},
        {"alpha alpha-5f1c0a9e7d3b2468 extra\n", "clients_file:1", "space"},
        {"alpha alpha-5f1c0a9e\x01"
         "7d3b2468\n",
         "clients_file:1", "unprintable"},
        {"alpha alpha-5f1c0a9e7d3b2468\n\n\nbeta alpha-5f1c0a9e7d3b2468\n", "clients_file:4",
         "already given to client 'alpha'"},
    };
    for (const Case& c : cases) {
        auto tokens = ParseClientTokens(c.text);
        ASSERT_FALSE(tokens.ok()) << c.text;
        EXPECT_EQ(tokens.error().field, c.field) << c.text;
        EXPECT_NE(tokens.error().reason.find(c.reason), std::string::npos)
            << c.text << ": " << tokens.error().reason;
    }
}

// Holds one Render of `scene_id` open with `token` until destroyed (then cancels it).
// Server options for calls made beside a HeldRender: a second worker serves them while the
// Render holds the first. With one worker a call waited in the queue until the held stream's
// idle limit (stream_idle_seconds, 10 s) ended the Render, and the checks after it raced that
// end.
service::ServerOptions BesideAHeldRender(const std::string& instance) {
    service::ServerOptions options = SmallServerOptions(instance);
    options.service.workers = std::max(2, options.service.workers);
    return options;
}

class HeldRender {
  public:
    HeldRender(v1::Shadow::Stub& stub, const std::string& scene_id, const std::string& token) {
        WithDeadline(context_);
        if (!token.empty()) context_.AddMetadata("authorization", "Bearer " + token);
        reader_ = stub.Render(&context_, BigRender(scene_id));
        started_ = reader_->Read(&chunk_);
    }
    ~HeldRender() {
        context_.TryCancel();
        while (reader_->Read(&chunk_)) {
        }
        reader_->Finish();
    }
    bool started() const { return started_; }

  private:
    grpc::ClientContext context_;
    std::unique_ptr<grpc::ClientReader<v1::RenderChunk>> reader_;
    v1::RenderChunk chunk_;
    bool started_ = false;
};

TEST(ClientIdentity, EachClientTokenIsABudgetOfItsOwn) {
    service::ServerOptions options = BesideAHeldRender("test-client-tokens");
    options.service.client_tokens = {{kAlphaToken, "alpha"}, {kBetaToken, "beta"}};
    options.service.max_calls_per_client = 1;
    auto server = StartServer(options);
    ClientLimits& limits = server->service().state().limits;
    auto uploaded = Connect(Target(*server), kAlphaToken)->UploadScene(SmallScene());
    ASSERT_TRUE(uploaded.ok()) << uploaded.error().Message();
    ASSERT_TRUE(Eventually([&] { return limits.clients() == 0; }));
    auto stub = RawStub(Target(*server));
    {
        HeldRender held(*stub, uploaded->scene_id(), kAlphaToken);
        ASSERT_TRUE(held.started());
        EXPECT_EQ(limits.calls("client:alpha"), 1u);
        EXPECT_EQ(limits.calls(kLoopback), 0u);
        // alpha is at its limit; beta, from the same address, is not.
        const grpc::Status alpha = CallSolve(*stub, SmallSolve(), kAlphaToken);
        EXPECT_EQ(alpha.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
        EXPECT_NE(alpha.error_message().find("max_calls_per_client"), std::string::npos);
        EXPECT_TRUE(CallSolve(*stub, SmallSolve(), kBetaToken).ok());
        // beta's lease is given back when the call is done on the server, which may be just
        // after its answer reached us.
        ASSERT_TRUE(Eventually([&] { return limits.calls("client:beta") == 0; }));
        // No token, a wrong one, or one that differs only in its last character: not let in,
        // and nothing counted.
        for (const std::string& token : {std::string(), std::string("beta-0d9e8c7b6a594838"),
                                         std::string(kAlphaToken) + " "}) {
            const grpc::Status refused = CallSolve(*stub, SmallSolve(), token);
            EXPECT_EQ(refused.error_code(), grpc::StatusCode::UNAUTHENTICATED) << token;
            EXPECT_EQ(refused.error_message(), "authorization: missing or wrong bearer token");
        }
        EXPECT_EQ(limits.clients(), 1u);  // alpha's held Render alone
        EXPECT_EQ(limits.calls("client:alpha"), 1u);
    }
    ASSERT_TRUE(Eventually([&] { return limits.clients() == 0; }));
    EXPECT_TRUE(CallSolve(*stub, SmallSolve(), kAlphaToken).ok());
}

TEST(ClientIdentity, ASharedTokenAuthorisesButTheAddressIdentifies) {
    service::ServerOptions options = BesideAHeldRender("test-shared-token");
    options.service.bearer_token = "s3cret";
    options.service.client_tokens = {{kAlphaToken, "alpha"}};
    options.service.max_calls_per_client = 1;
    auto server = StartServer(options);
    ClientLimits& limits = server->service().state().limits;
    auto uploaded = Connect(Target(*server), "s3cret")->UploadScene(SmallScene());
    ASSERT_TRUE(uploaded.ok()) << uploaded.error().Message();
    ASSERT_TRUE(Eventually([&] { return limits.clients() == 0; }));
    auto stub = RawStub(Target(*server));
    {
        HeldRender held(*stub, uploaded->scene_id(), "s3cret");
        ASSERT_TRUE(held.started());
        EXPECT_EQ(limits.calls(kLoopback), 1u);
        // Authorisation comes before admission: no token is UNAUTHENTICATED even with the
        // address's budget full; the shared token is refused for the budget; alpha's own token
        // is a budget of its own.
        EXPECT_EQ(CallSolve(*stub, SmallSolve()).error_code(), grpc::StatusCode::UNAUTHENTICATED);
        EXPECT_EQ(CallSolve(*stub, SmallSolve(), "s3cret").error_code(),
                  grpc::StatusCode::RESOURCE_EXHAUSTED);
        EXPECT_TRUE(CallSolve(*stub, SmallSolve(), kAlphaToken).ok());
    }
    ASSERT_TRUE(Eventually([&] { return limits.clients() == 0; }));
    EXPECT_TRUE(CallSolve(*stub, SmallSolve(), "s3cret").ok());
}

std::unique_ptr<v1::Shadow::Stub> MutualTlsStub(int port, const TestCa& ca,
                                                const std::string& client) {
    grpc::SslCredentialsOptions tls;
    tls.pem_root_certs = ca.File("ca.pem");
    tls.pem_cert_chain = ca.File(client + ".pem");
    tls.pem_private_key = ca.File(client + ".key");
    grpc::ChannelArguments arguments;
    arguments.SetSslTargetNameOverride("localhost");
    return v1::Shadow::NewStub(grpc::CreateCustomChannel("127.0.0.1:" + std::to_string(port),
                                                         grpc::SslCredentials(tls), arguments));
}

TEST(ClientIdentity, MutualTlsClientsAreCountedByCertificateSubject) {
    TestCa ca;
    ASSERT_TRUE(ca.ok()) << "openssl could not make the test CA";
    service::ServerOptions options = BesideAHeldRender("test-mtls-identity");
    ca.ServeTls(options, true);
    options.service.max_calls_per_client = 1;
    auto server = StartServer(options);
    ClientLimits& limits = server->service().state().limits;
    auto first = MutualTlsStub(server->port(), ca, "client");
    auto second = MutualTlsStub(server->port(), ca, "client2");

    auto uploaded = ca.Client(server->port(), "client", 60.0)->UploadScene(SmallScene());
    ASSERT_TRUE(uploaded.ok()) << uploaded.error().Message();
    ASSERT_TRUE(Eventually([&] { return limits.clients() == 0; }));
    {
        HeldRender held(*first, uploaded->scene_id(), "");
        ASSERT_TRUE(held.started());
        EXPECT_EQ(limits.calls("cert:lixel-client"), 1u);
        EXPECT_EQ(CallSolve(*first, SmallSolve()).error_code(),
                  grpc::StatusCode::RESOURCE_EXHAUSTED);
        EXPECT_TRUE(CallSolve(*second, SmallSolve()).ok());
        EXPECT_EQ(limits.calls(kLoopback), 0u);
    }
    ASSERT_TRUE(Eventually([&] { return limits.clients() == 0; }));
}

}  // namespace
}  // namespace lixel
