// Tests for the service's TLS: a test CA made at test time signs the server's certificate (and a
// client's, for mutual TLS); clients that trust the CA get in, plaintext clients do not.
#include "service_fixture.h"
#include "test_ca.h"

namespace lixel {
namespace {

using testing::SmallScene;
using testing::SmallServerOptions;
using testing::StartServer;
using testing::TestCa;

TEST(ServiceTls, TrustedClientsGetInAndPlaintextOnesDoNot) {
    TestCa ca;
    ASSERT_TRUE(ca.ok()) << "openssl could not make the test CA";
    service::ServerOptions options = SmallServerOptions("test-tls");
    ca.ServeTls(options, false);
    auto server = StartServer(options);
    auto trusted = ca.Client(server->port(), "");
    auto uploaded = trusted->UploadScene(SmallScene());
    ASSERT_TRUE(uploaded.ok()) << uploaded.error().Message();

    client::ClientOptions plain;
    plain.target = "127.0.0.1:" + std::to_string(server->port());
    plain.deadline_seconds = 3.0;
    plain.retries = 0;
    auto plaintext = std::move(client::Client::Connect(plain)).value();
    auto refused = plaintext->UploadScene(SmallScene());
    ASSERT_FALSE(refused.ok());
    EXPECT_TRUE(refused.error().field == "UNAVAILABLE" ||
                refused.error().field == "DEADLINE_EXCEEDED")
        << refused.error().Message();
}

TEST(ServiceTls, MutualTlsWantsAClientCertificate) {
    TestCa ca;
    ASSERT_TRUE(ca.ok());
    service::ServerOptions options = SmallServerOptions("test-mtls");
    ca.ServeTls(options, true);
    auto server = StartServer(options);
    auto with = ca.Client(server->port(), "client");
    auto uploaded = with->UploadScene(SmallScene());
    EXPECT_TRUE(uploaded.ok()) << uploaded.error().Message();
    auto without = ca.Client(server->port(), "", 3.0);
    auto refused = without->UploadScene(SmallScene());
    EXPECT_FALSE(refused.ok());
}

}  // namespace
}  // namespace lixel
