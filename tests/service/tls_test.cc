// Tests for the service's TLS: a test CA made at test time signs the server's certificate (and a
// client's, for mutual TLS); clients that trust the CA get in, plaintext clients do not.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <unistd.h>

#include "service_fixture.h"

namespace lixel {
namespace {

using testing::SmallScene;
using testing::SmallServerOptions;
using testing::StartServer;

std::string Read(const std::filesystem::path& path) {
    std::ifstream in(path);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

// A CA, a server certificate for 127.0.0.1 / localhost, and a client certificate, in a fresh
// temporary folder, made with the openssl command.
class TestCa {
public:
    TestCa() {
        dir_ = std::filesystem::temp_directory_path() /
               ("lixel-ca-" + std::to_string(::getpid()));
        std::filesystem::create_directories(dir_);
        const std::string d = dir_.string();
        const std::string script =
            "set -e; cd " + d + "; "
            "openssl req -x509 -newkey rsa:2048 -nodes -days 1 -subj /CN=lixel-test-ca "
            "-keyout ca.key -out ca.pem 2>/dev/null; "
            "printf 'subjectAltName=IP:127.0.0.1,DNS:localhost' > san.ext; "
            "openssl req -newkey rsa:2048 -nodes -subj /CN=localhost -keyout server.key "
            "-out server.csr 2>/dev/null; "
            "openssl x509 -req -in server.csr -CA ca.pem -CAkey ca.key -CAcreateserial -days 1 "
            "-extfile san.ext -out server.pem 2>/dev/null; "
            "openssl req -newkey rsa:2048 -nodes -subj /CN=lixel-client -keyout client.key "
            "-out client.csr 2>/dev/null; "
            "openssl x509 -req -in client.csr -CA ca.pem -CAkey ca.key -CAcreateserial -days 1 "
            "-out client.pem 2>/dev/null";
        ok_ = std::system(("bash -c '" + script + "'").c_str()) == 0;
    }
    ~TestCa() { std::filesystem::remove_all(dir_); }
    bool ok() const { return ok_; }
    std::string File(const char* name) const { return Read(dir_ / name); }

private:
    std::filesystem::path dir_;
    bool ok_ = false;
};

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
