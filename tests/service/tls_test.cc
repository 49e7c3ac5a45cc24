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

std::unique_ptr<client::Client> TlsClient(int port, const TestCa& ca, bool with_certificate,
                                          double deadline_seconds = 20.0) {
    client::ClientOptions options;
    options.target = "127.0.0.1:" + std::to_string(port);
    options.tls_root_certificate = ca.File("ca.pem");
    options.tls_server_name = "localhost";
    options.deadline_seconds = deadline_seconds;
    options.retries = 0;
    if (with_certificate) {
        options.tls_client_certificate = ca.File("client.pem");
        options.tls_client_key = ca.File("client.key");
    }
    return std::move(client::Client::Connect(options)).value();
}

TEST(ServiceTls, TrustedClientsGetInAndPlaintextOnesDoNot) {
    TestCa ca;
    ASSERT_TRUE(ca.ok()) << "openssl could not make the test CA";
    service::ServerOptions options = SmallServerOptions("test-tls");
    options.tls_certificate = ca.File("server.pem");
    options.tls_private_key = ca.File("server.key");
    auto server = StartServer(options);
    auto trusted = TlsClient(server->port(), ca, false);
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
    options.tls_certificate = ca.File("server.pem");
    options.tls_private_key = ca.File("server.key");
    options.tls_client_ca = ca.File("ca.pem");
    auto server = StartServer(options);
    auto with = TlsClient(server->port(), ca, true);
    auto uploaded = with->UploadScene(SmallScene());
    EXPECT_TRUE(uploaded.ok()) << uploaded.error().Message();
    auto without = TlsClient(server->port(), ca, false, 3.0);
    auto refused = without->UploadScene(SmallScene());
    EXPECT_FALSE(refused.ok());
}

}  // namespace
}  // namespace lixel
