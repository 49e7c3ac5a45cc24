// A test certificate authority made at test time with the openssl command: a CA, a server
// certificate for 127.0.0.1 / localhost, and two client certificates (subjects lixel-client and
// lixel-client-2) for mutual TLS, in a fresh temporary folder removed afterwards.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <fstream>
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

private:
    std::filesystem::path dir_;
    bool ok_ = false;
};

}  // namespace lixel::testing
