// `napkin serve` safe by default (docs/serve.md "Safety") and its stop on
// SIGTERM: the built binary, a loopback port, every wait bounded.
#include <gtest/gtest.h>
#include <sqlite3.h>
#include <sys/stat.h>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/error.h"
#include "serve/api.h"
#include "serve/service.h"
#include "tests/serve/serve_test_util.h"
#include "tests/support/test_support.h"

namespace napkin::test_support {
namespace {

using Json = nlohmann::json;

class ServeSafety : public ServeCatalogueTest {
 protected:
  CommandResult Serve(const std::vector<std::string>& args) {
    std::vector<std::string> all = {"--db", db().string(), "serve"};
    all.insert(all.end(), args.begin(), args.end());
    return RunProgram(NAPKIN_BINARY, all, dir_.path());
  }
};

TEST_F(ServeSafety, NonLoopbackWithoutTokenIsRefusedAtStart) {
  for (const std::string& address : std::vector<std::string>{"0.0.0.0:0", "[::]:0", "192.0.2.1:8080"}) {
    const CommandResult run = Serve({"--listen", address});
    EXPECT_EQ(run.exit_code, 2) << address;
    EXPECT_EQ(run.err, "napkin: --listen " + address +
                           " is not a loopback address, which napkin serve answers only with --token-file (a "
                           "bearer token every request must carry).\n");
  }
  const CommandResult bad = Serve({"--listen", "localhost"});
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_EQ(bad.err,
            "napkin: --listen 'localhost' has no host and port (give HOST:PORT, e.g. 127.0.0.1:8080).\n");
  const CommandResult missing =
      RunProgram(NAPKIN_BINARY, {"--db", "none.db", "serve", "--listen", "127.0.0.1:0"}, dir_.path());
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_EQ(std::count(missing.err.begin(), missing.err.end(), '\n'), 1) << missing.err;
}

TEST_F(ServeSafety, ShortTokenFileIsRefused) {
  std::ofstream(dir_ / "token") << "short\n";
  const CommandResult run = Serve({"--listen", "127.0.0.1:0", "--token-file", (dir_ / "token").string()});
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("holds a token shorter than 16 characters"), std::string::npos) << run.err;
}

// A token file is a regular file of bounded size, opened without blocking, that only its owner may
// write; one others may read is warned about (issue 42, point 7: /dev/zero was read until 2.2 GB, a
// FIFO blocked the start forever, a folder was "cannot be read").
TEST_F(ServeSafety, TokenFilesThatAreNotPrivateRegularFilesAreRefused) {
  const std::string token = "d2hhdCBhIGxvbmcgcmFuZG9tIHRva2Vu\n";
  const fs::path fifo = dir_ / "fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const fs::path writable = dir_ / "writable";
  WriteText(writable, token);
  fs::permissions(writable, fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_write);
  const fs::path large = dir_ / "large";
  WriteText(large, std::string(5000, 'x'));
  fs::permissions(large, fs::perms::owner_read | fs::perms::owner_write);
  const std::vector<std::pair<std::string, std::string>> refused = {
      {"/dev/zero", "--token-file '/dev/zero' is not a regular file"},
      {fifo.string(), "--token-file '" + fifo.string() + "' is not a regular file"},
      {dir_.path().string(), "--token-file '" + dir_.path().string() + "' is a folder"},
      {writable.string(),
       "--token-file '" + writable.string() + "' may be written by other users (mode 0620)"},
      {large.string(), "--token-file '" + large.string() + "' is 5000 bytes, more than the 4096"}};
  for (const auto& [file, sentence] : refused) {
    const auto start = std::chrono::steady_clock::now();
    ServeProcess serve(dir_.path(), db(), {"--listen", "127.0.0.1:0", "--token-file", file});
    EXPECT_EQ(serve.port(), 0) << file;
    EXPECT_EQ(serve.exit_code(), 1) << file << "\n" << serve.log();
    const std::string log = serve.log();
    EXPECT_NE(log.find(sentence), std::string::npos) << log;
    EXPECT_EQ(std::count(log.begin(), log.end(), '\n'), 1) << log;
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(20)) << file;
  }
  // Readable by others: it starts, and says so.
  const fs::path readable = dir_ / "readable";
  WriteText(readable, token);
  fs::permissions(readable, fs::perms::owner_read | fs::perms::owner_write | fs::perms::others_read);
  {
    ServeProcess serve(dir_.path(), db(), {"--listen", "127.0.0.1:0", "--token-file", readable.string()});
    ASSERT_GT(serve.port(), 0) << serve.log();
    EXPECT_NE(
        serve.log().find("--token-file '" + readable.string() + "' may be read by other users (mode 0604)"),
        std::string::npos)
        << serve.log();
    EXPECT_EQ(serve.Stop(), 0);
  }
  fs::permissions(readable, fs::perms::owner_read | fs::perms::owner_write);
  ServeProcess serve(dir_.path(), db(), {"--listen", "127.0.0.1:0", "--token-file", readable.string()});
  ASSERT_GT(serve.port(), 0) << serve.log();
  EXPECT_EQ(serve.log().find("may be read by other users"), std::string::npos) << serve.log();
  EXPECT_EQ(serve.Stop(), 0);
}

TEST_F(ServeSafety, TokenGuardsEveryRouteButHealthz) {
  const std::string token = "d2hhdCBhIGxvbmcgcmFuZG9tIHRva2Vu";
  std::ofstream(dir_ / "token") << token << "\n";
  ServeProcess serve(dir_.path(), db(),
                     {"--listen", "127.0.0.1:0", "--token-file", (dir_ / "token").string()});
  ASSERT_GT(serve.port(), 0) << serve.log();
  const auto client = serve.Client();
  EXPECT_EQ(client->Get("/healthz")->status, 200);
  const httplib::Result none = client->Get("/api/v1/tests");
  ASSERT_TRUE(none);
  EXPECT_EQ(none->status, 401);
  EXPECT_EQ(none->get_header_value("WWW-Authenticate"), "Bearer");
  EXPECT_TRUE(Json::parse(none->body).contains("error"));
  for (const std::string& wrong :
       {token + "x", token.substr(0, token.size() - 1), std::string("Bearer"), std::string()})
    EXPECT_EQ(client->Get("/api/v1/tests", {{"Authorization", "Bearer " + wrong}})->status, 401) << wrong;
  EXPECT_EQ(client->Get("/api/v1/tests", {{"Authorization", "Basic " + token}})->status, 401);
  const httplib::Result right = client->Get("/api/v1/tests", {{"Authorization", "Bearer " + token}});
  ASSERT_TRUE(right);
  EXPECT_EQ(right->status, 200);
  EXPECT_EQ(right->body, "[]\n");
  EXPECT_EQ(client->Get("/metrics")->status, 401);
  EXPECT_EQ(serve.Stop(), 0);
}

// The scheme is case-insensitive (RFC 9110), and the whole field is the token: nothing after a NUL
// passes (issue 42, point 11: "bearer" was refused, "Bearer TOKEN\0junk" accepted). A NUL in a
// field is a malformed request (RFC 9110 5.5), refused before the token is looked at.
TEST_F(ServeSafety, BearerSchemeInAnyCaseAndNoTrailingBytesAfterTheToken) {
  const std::string token = "d2hhdCBhIGxvbmcgcmFuZG9tIHRva2Vu";
  WriteText(dir_ / "token", token + "\n");
  fs::permissions(dir_ / "token", fs::perms::owner_read | fs::perms::owner_write);
  ServeProcess serve(dir_.path(), db(),
                     {"--listen", "127.0.0.1:0", "--token-file", (dir_ / "token").string()});
  ASSERT_GT(serve.port(), 0) << serve.log();
  const auto status_of = [&](const std::string& authorization) {
    const std::string answer = RawExchange(serve.port(),
                                           "GET /api/v1/tests HTTP/1.1\r\nHost: localhost\r\n"
                                           "Connection: close\r\nAuthorization: " +
                                               authorization + "\r\n\r\n");
    return answer.substr(0, answer.find("\r\n"));
  };
  EXPECT_EQ(status_of("Bearer " + token), "HTTP/1.1 200 OK");
  EXPECT_EQ(status_of("bearer " + token), "HTTP/1.1 200 OK");
  EXPECT_EQ(status_of("BEARER " + token), "HTTP/1.1 200 OK");
  EXPECT_EQ(status_of("Bearer " + token + std::string(1, '\0') + "junk"), "HTTP/1.1 400 Bad Request");
  EXPECT_EQ(status_of("Bearer " + token.substr(0, 16) + std::string(1, '\0') + token.substr(16)),
            "HTTP/1.1 400 Bad Request");
  EXPECT_EQ(status_of("Bearer " + token + "x"), "HTTP/1.1 401 Unauthorized");
  EXPECT_EQ(serve.Stop(), 0);
}

// The header limit counts the client's fields only (issue 42, point 11: httplib's four entries of
// the connection's addresses were counted too, so 97 fields were "101").
TEST_F(ServeSafety, TheHeaderLimitCountsTheClientsFields) {
  ServeProcess serve(dir_.path(), db(), {"--listen", "127.0.0.1:0"});
  ASSERT_GT(serve.port(), 0) << serve.log();
  const auto request_with = [](int fields) {
    std::string request = "GET /healthz HTTP/1.1\r\nHost: localhost\r\nConnection: close\r\n";
    for (int i = 2; i < fields; ++i) request += "X-Field-" + std::to_string(i) + ": v\r\n";
    return request + "\r\n";
  };
  const std::string hundred = RawExchange(serve.port(), request_with(100));
  EXPECT_EQ(hundred.rfind("HTTP/1.1 200", 0), 0u) << hundred;
  const std::string more = RawExchange(serve.port(), request_with(101));
  EXPECT_EQ(more.rfind("HTTP/1.1 431", 0), 0u) << more;
  EXPECT_NE(more.find("the request has 101 header fields"), std::string::npos) << more;
  EXPECT_EQ(serve.Stop(), 0);
}

TEST_F(ServeSafety, SigtermStopsWithStatusZero) {
  ServeProcess serve(dir_.path(), db(), {"--listen", "127.0.0.1:0"});
  ASSERT_GT(serve.port(), 0) << serve.log();
  EXPECT_EQ(serve.Client()->Get("/healthz")->status, 200);
  EXPECT_EQ(serve.Stop(SIGTERM), 0) << serve.log();
  EXPECT_NE(serve.log().find("SIGTERM: stopping"), std::string::npos) << serve.log();
  // No longer accepting.
  httplib::Client after("127.0.0.1", serve.port());
  after.set_connection_timeout(2, 0);
  EXPECT_FALSE(after.Get("/healthz"));
}

TEST_F(ServeSafety, LockedCatalogueIsA503SayingSo) {
  ServeProcess serve(dir_.path(), db(), {"--listen", "127.0.0.1:0", "--busy-timeout", "1"});
  ASSERT_GT(serve.port(), 0) << serve.log();
  sqlite3* holder = nullptr;
  ASSERT_EQ(sqlite3_open(db().c_str(), &holder), SQLITE_OK);
  // An exclusive lock (rollback journal for this connection's transaction): readers wait.
  ASSERT_EQ(sqlite3_exec(holder,
                         "PRAGMA locking_mode=EXCLUSIVE; BEGIN EXCLUSIVE; "
                         "CREATE TABLE held_by_test(x); INSERT INTO held_by_test VALUES (1);",
                         nullptr, nullptr, nullptr),
            SQLITE_OK)
      << sqlite3_errmsg(holder);
  const httplib::Result locked = serve.Client()->Get("/api/v1/query/hic");
  ASSERT_TRUE(locked);
  EXPECT_EQ(locked->status, 503) << locked->body;
  EXPECT_NE(Json::parse(locked->body).at("error").get<std::string>().find("is busy"), std::string::npos);
  // The status still answers, and says why the catalogue's counts are missing.
  const httplib::Result status = serve.Client()->Get("/api/v1/status");
  ASSERT_TRUE(status);
  EXPECT_EQ(status->status, 200);
  EXPECT_NE(Json::parse(status->body).at("catalogue").at("error").get<std::string>().find("is busy"),
            std::string::npos)
      << status->body;
  ASSERT_EQ(sqlite3_exec(holder, "ROLLBACK; PRAGMA locking_mode=NORMAL;", nullptr, nullptr, nullptr),
            SQLITE_OK);
  sqlite3_close(holder);
  // The next request after the lock is released (an exclusive-mode connection releases it on close).
  EXPECT_EQ(serve.Client()->Get("/api/v1/query/hic")->status, 200);
  EXPECT_EQ(serve.Stop(), 0);
}

TEST(ServeOptions, ListenAddressesAndLoopback) {
  EXPECT_EQ(serve::ParseListenAddress("127.0.0.1:8080").host, "127.0.0.1");
  EXPECT_EQ(serve::ParseListenAddress("127.0.0.1:8080").port, 8080);
  EXPECT_EQ(serve::ParseListenAddress("[::1]:0").host, "::1");
  EXPECT_THROW(serve::ParseListenAddress("::1:80"), UsageError);
  EXPECT_THROW(serve::ParseListenAddress("host:65536"), UsageError);
  EXPECT_THROW(serve::ParseListenAddress("host:"), UsageError);
  EXPECT_THROW(serve::ParseListenAddress(":80"), UsageError);
  EXPECT_TRUE(serve::IsLoopbackHost("127.0.0.1"));
  EXPECT_TRUE(serve::IsLoopbackHost("127.1.2.3"));
  EXPECT_TRUE(serve::IsLoopbackHost("::1"));
  EXPECT_TRUE(serve::IsLoopbackHost("localhost"));
  EXPECT_FALSE(serve::IsLoopbackHost("0.0.0.0"));
  EXPECT_FALSE(serve::IsLoopbackHost("127.0.0.1.example.com"));
  EXPECT_FALSE(serve::IsLoopbackHost("::"));
}

TEST(ServeOptions, TokensEqualOnlyWhenEqual) {
  EXPECT_TRUE(serve::TokensEqual("abcdefghijklmnop", "abcdefghijklmnop"));
  EXPECT_FALSE(serve::TokensEqual("abcdefghijklmnoq", "abcdefghijklmnop"));
  EXPECT_FALSE(serve::TokensEqual("abcdefghijklmno", "abcdefghijklmnop"));
  EXPECT_FALSE(serve::TokensEqual("abcdefghijklmnopq", "abcdefghijklmnop"));
  EXPECT_FALSE(serve::TokensEqual("", "abcdefghijklmnop"));
  // A prefix padded with NULs is not the token either.
  EXPECT_FALSE(serve::TokensEqual(std::string("abcdefghijklmno\0", 16), "abcdefghijklmnoz"));
}

TEST(ServeErrors, CategoriesGiveTheirStatus) {
  const auto status = [](const std::exception_ptr& error) {
    return serve::ErrorResponse(error, "lab.db").status;
  };
  EXPECT_EQ(status(std::make_exception_ptr(UsageError("bad where."))), 400);
  EXPECT_EQ(status(std::make_exception_ptr(InputError("bad file."))), 400);
  EXPECT_EQ(status(std::make_exception_ptr(NotFoundError("no test."))), 404);
  EXPECT_EQ(status(std::make_exception_ptr(std::logic_error("bug"))), 500);
  const serve::Response response =
      serve::ErrorResponse(std::make_exception_ptr(NotFoundError("no test.")), "lab.db");
  EXPECT_EQ(response.body, "{\"error\":\"no test.\"}\n");
}

}  // namespace
}  // namespace napkin::test_support
