// A test certificate authority made at test time with the openssl command: a CA, a server
// certificate for 127.0.0.1 / localhost, and two client certificates (subjects lixel-client and
// lixel-client-2) for mutual TLS, in a fresh temporary folder removed afterwards.
#pragma once

#include <lixel/client/client.h>
#include <lixel/service/server.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>

#include <unistd.h>

namespace lixel::testing {

class TestCa {
public:
    TestCa() {
        static int made = 0;
        dir_ = std::filesystem::temp_directory_path() /
               ("lixel-ca-" + std::to_string(::getpid()) + "-" + std::to_string(made++));
        std::filesystem::create_directories(dir_);
        std::string script =
            "set -e; cd " + dir_.string() + "; "
            "openssl req -x509 -newkey rsa:2048 -nodes -days 1 -subj /CN=lixel-test-ca "
            "-keyout ca.key -out ca.pem 2>/dev/null; "
            "printf 'subjectAltName=IP:127.0.0.1,DNS:localhost' > san.ext; "
            "openssl req -newkey rsa:2048 -nodes -subj /CN=localhost -keyout server.key "
            "-out server.csr 2>/dev/null; "
            "openssl x509 -req -in server.csr -CA ca.pem -CAkey ca.key -CAcreateserial -days 1 "
            "-extfile san.ext -out server.pem 2>/dev/null; ";
        for (const char* name : {"client", "client2"}) {
            const std::string n = name;
            const std::string subject = n == "client" ? "lixel-client" : "lixel-client-2";
            script += "openssl req -newkey rsa:2048 -nodes -subj /CN=" + subject + " -keyout " +
                      n + ".key -out " + n + ".csr 2>/dev/null; "
                      "openssl x509 -req -in " + n + ".csr -CA ca.pem -CAkey ca.key "
                      "-CAcreateserial -days 1 -out " + n + ".pem 2>/dev/null; ";
        }
        ok_ = std::system(("bash -c '" + script + "'").c_str()) == 0;
    }
    ~TestCa() { std::filesystem::remove_all(dir_); }
    TestCa(const TestCa&) = delete;
    TestCa& operator=(const TestCa&) = delete;

    bool ok() const { return ok_; }
    std::string File(const std::string& name) const {
        std::ifstream in(dir_ / name);
        std::ostringstream text;
        text << in.rdbuf();
        return text.str();
    }

    // Serves TLS with the server certificate; `mutual`: clients must present one the CA signed.
    void ServeTls(service::ServerOptions& options, bool mutual) const {
        options.tls_certificate = File("server.pem");
        options.tls_private_key = File("server.key");
        if (mutual) options.tls_client_ca = File("ca.pem");
    }

    // A client that trusts the CA, with `certificate` ("client", "client2") or none ("").
    std::unique_ptr<client::Client> Client(int port, const std::string& certificate,
                                           double deadline_seconds = 20.0) const {
        client::ClientOptions options;
        options.target = "127.0.0.1:" + std::to_string(port);
        options.tls_root_certificate = File("ca.pem");
        options.tls_server_name = "localhost";
        options.deadline_seconds = deadline_seconds;
        options.retries = 0;
        if (!certificate.empty()) {
            options.tls_client_certificate = File(certificate + ".pem");
            options.tls_client_key = File(certificate + ".key");
        }
        return std::move(client::Client::Connect(options)).value();
    }

private:
    std::filesystem::path dir_;
    bool ok_ = false;
};

}  // namespace lixel::testing
