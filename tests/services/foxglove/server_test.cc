// The Foxglove WebSocket protocol server against clients on this machine:
// a websocketpp client that speaks foxglove.websocket.v1 (serverInfo,
// advertise, subscribe, binary message and time frames, error statuses),
// one without the subprotocol, and a raw socket that subscribes and then
// never reads, which is held back and closed while a reading client still
// gets every message.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstring>
#include <mutex>
#include <thread>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <websocketpp/client.hpp>
#include <websocketpp/config/asio_no_tls_client.hpp>

#include "services/foxglove/server.h"

namespace hcosim::services::foxglove {
namespace {

using json = nlohmann::json;
using WsClient = websocketpp::client<websocketpp::config::asio_client>;

// A client that keeps every text (as JSON) and binary message it gets.
class Client {
 public:
  explicit Client(int port, bool with_subprotocol = true) {
    ws_.clear_access_channels(websocketpp::log::alevel::all);
    ws_.clear_error_channels(websocketpp::log::elevel::all);
    ws_.init_asio();
    ws_.set_open_handler([this](websocketpp::connection_hdl) { note([&] { open_ = true; }); });
    ws_.set_fail_handler([this](websocketpp::connection_hdl) { note([&] { failed_ = true; }); });
    ws_.set_close_handler([this](websocketpp::connection_hdl) { note([&] { closed_ = true; }); });
    ws_.set_message_handler([this](websocketpp::connection_hdl, WsClient::message_ptr m) {
      note([&] {
        if (m->get_opcode() == websocketpp::frame::opcode::text)
          texts_.push_back(json::parse(m->get_payload()));
        else
          binaries_.push_back(m->get_payload());
      });
    });
    websocketpp::lib::error_code ec;
    con_ = ws_.get_connection("ws://127.0.0.1:" + std::to_string(port), ec);
    if (with_subprotocol) con_->add_subprotocol(Server::kSubprotocol);
    ws_.connect(con_);
    thread_ = std::thread([this] { ws_.run(); });
  }
  ~Client() {
    websocketpp::lib::error_code ec;
    if (open_ && !closed_) con_->close(websocketpp::close::status::normal, "", ec);
    for (int i = 0; i < 100 && !closed_ && open_; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    ws_.stop();
    thread_.join();
  }
  void send(const json& j) { con_->send(j.dump(), websocketpp::frame::opcode::text); }
  void send_text(const std::string& s) { con_->send(s, websocketpp::frame::opcode::text); }
  // Waits up to 5 s for `done` to hold over what arrived.
  template <class F>
  bool wait(F&& done) {
    std::unique_lock<std::mutex> l(m_);
    return cv_.wait_for(l, std::chrono::seconds(5), [&] { return done(); });
  }
  bool open_ = false, failed_ = false, closed_ = false;
  std::vector<json> texts_;
  std::vector<std::string> binaries_;
  std::mutex m_;

 private:
  template <class F>
  void note(F&& f) {
    {
      std::lock_guard<std::mutex> l(m_);
      f();
    }
    cv_.notify_all();
  }
  WsClient ws_;
  WsClient::connection_ptr con_;
  std::thread thread_;
  std::condition_variable cv_;
};

std::uint64_t le(const std::string& b, std::size_t at, int bytes) {
  std::uint64_t v = 0;
  for (int i = 0; i < bytes; ++i) v |= std::uint64_t(std::uint8_t(b[at + i])) << (8 * i);
  return v;
}

Channel channel(const std::string& topic) { return {topic, "cdr", "hcosim::" + topic, "struct X {};", "omgidl"}; }

bool eventually(const std::function<bool()>& f) {
  for (int i = 0; i < 500; ++i) {
    if (f()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return false;
}

std::size_t count_op(const std::vector<json>& texts, const std::string& op) {
  std::size_t n = 0;
  for (const json& t : texts) n += t.value("op", "") == op;
  return n;
}

TEST(FoxgloveServer, AdvertisesAndSendsOnlySubscribedChannelsAndTheTime) {
  ServerOptions o;
  o.port = 0;
  Server server(o);
  EXPECT_EQ(server.advertise(channel("A")), 0u);
  EXPECT_EQ(server.advertise(channel("B")), 1u);
  Client c(server.port());
  ASSERT_TRUE(c.wait([&] { return c.texts_.size() >= 2; }));
  {
    std::lock_guard<std::mutex> l(c.m_);
    const json& info = c.texts_[0];
    EXPECT_EQ(info["op"], "serverInfo");
    EXPECT_EQ(info["name"], "hcosim");
    EXPECT_EQ(info["capabilities"], json::array({"time"}));
    const json& ad = c.texts_[1];
    ASSERT_EQ(ad["op"], "advertise");
    ASSERT_EQ(ad["channels"].size(), 2u);
    EXPECT_EQ(ad["channels"][1]["id"], 1);
    EXPECT_EQ(ad["channels"][1]["topic"], "B");
    EXPECT_EQ(ad["channels"][1]["encoding"], "cdr");
    EXPECT_EQ(ad["channels"][1]["schemaName"], "hcosim::B");
    EXPECT_EQ(ad["channels"][1]["schemaEncoding"], "omgidl");
  }
  c.send({{"op", "subscribe"}, {"subscriptions", {{{"id", 7}, {"channelId", 1}}}}});
  ASSERT_TRUE(eventually([&] { return server.subscribed(1); }));
  EXPECT_FALSE(server.subscribed(0));
  server.publish(0, 5, {9, 9});  // nobody's
  server.publish(1, 123456789012345ull, {1, 2, 3});
  server.time(42);
  ASSERT_TRUE(c.wait([&] { return c.binaries_.size() >= 2; }));
  {
    std::lock_guard<std::mutex> l(c.m_);
    ASSERT_EQ(c.binaries_.size(), 2u);
    const std::string& m = c.binaries_[0];
    ASSERT_EQ(m.size(), 1u + 4 + 8 + 3);
    EXPECT_EQ(m[0], 1);                          // message data
    EXPECT_EQ(le(m, 1, 4), 7u);                  // the client's subscription id
    EXPECT_EQ(le(m, 5, 8), 123456789012345ull);  // its time
    EXPECT_EQ(m.substr(13), std::string("\x01\x02\x03", 3));
    const std::string& t = c.binaries_[1];
    ASSERT_EQ(t.size(), 9u);
    EXPECT_EQ(t[0], 2);  // time
    EXPECT_EQ(le(t, 1, 8), 42u);
  }
  // A channel advertised later reaches a connected client.
  EXPECT_EQ(server.advertise(channel("C")), 2u);
  ASSERT_TRUE(c.wait([&] { return count_op(c.texts_, "advertise") == 2; }));
  c.send({{"op", "unsubscribe"}, {"subscriptionIds", {7}}});
  ASSERT_TRUE(eventually([&] { return !server.subscribed(1); }));
  EXPECT_EQ(server.counters().sent, 1u);
  EXPECT_EQ(server.counters().refused, 0u);
}

// The bridge draws in every_flush()'s hook: it runs on the socket thread,
// what it publishes goes out in the same wake-up, and after
// every_flush(nullptr) it never runs again.
TEST(FoxgloveServer, EveryFlushRunsItsHookOnTheSocketThreadUntilTakenAway) {
  ServerOptions o;
  o.port = 0;
  Server server(o);
  server.advertise(channel("A"));
  Client c(server.port());
  ASSERT_TRUE(c.wait([&] { return c.texts_.size() >= 2; }));
  c.send({{"op", "subscribe"}, {"subscriptions", {{{"id", 3}, {"channelId", 0}}}}});
  ASSERT_TRUE(eventually([&] { return server.subscribed(0); }));
  std::atomic<int> calls{0};
  std::atomic<bool> elsewhere{false};
  const std::thread::id here = std::this_thread::get_id();
  server.every_flush([&] {
    if (std::this_thread::get_id() == here) elsewhere = true;
    const int n = ++calls;
    if (n <= 3) server.publish(0, std::uint64_t(n), {std::uint8_t(n)});
  });
  ASSERT_TRUE(c.wait([&] { return c.binaries_.size() >= 3; }));
  server.every_flush(nullptr);
  const int after = calls;
  std::this_thread::sleep_for(std::chrono::milliseconds(100));  // ten periods
  EXPECT_EQ(calls, after);
  EXPECT_GE(after, 3);
  EXPECT_FALSE(elsewhere);
  std::lock_guard<std::mutex> l(c.m_);
  ASSERT_EQ(c.binaries_.size(), 3u);
  for (int n = 1; n <= 3; ++n) {
    EXPECT_EQ(le(c.binaries_[n - 1], 5, 8), std::uint64_t(n));
    EXPECT_EQ(c.binaries_[n - 1].substr(13), std::string(1, char(n)));
  }
}

TEST(FoxgloveServer, BadRequestsAreAnsweredWithAnErrorStatusThatNamesThem) {
  ServerOptions o;
  o.port = 0;
  Server server(o);
  server.advertise(channel("A"));
  Client c(server.port());
  ASSERT_TRUE(c.wait([&] { return c.texts_.size() >= 2; }));
  c.send({{"op", "subscribe"}, {"subscriptions", {{{"id", 1}, {"channelId", 5}}}}});
  c.send({{"op", "subscribe"}, {"subscriptions", {{{"id", 1}, {"channelId", 0}}}}});
  c.send({{"op", "subscribe"}, {"subscriptions", {{{"id", 1}, {"channelId", 0}}}}});
  c.send({{"op", "unsubscribe"}, {"subscriptionIds", {3}}});
  c.send_text("{not json");
  c.send({{"op", "subscribe"}});
  ASSERT_TRUE(c.wait([&] { return count_op(c.texts_, "status") >= 5; }));
  std::vector<std::string> said;
  {
    std::lock_guard<std::mutex> l(c.m_);
    for (const json& t : c.texts_)
      if (t["op"] == "status") {
        EXPECT_EQ(t["level"], 2);
        said.push_back(t["message"]);
      }
  }
  ASSERT_EQ(said.size(), 5u);
  EXPECT_NE(said[0].find("no channel 5"), std::string::npos) << said[0];
  EXPECT_NE(said[1].find("subscription id 1 is in use"), std::string::npos) << said[1];
  EXPECT_NE(said[2].find("no subscription 3"), std::string::npos) << said[2];
  EXPECT_NE(said[3].find("not a JSON object"), std::string::npos) << said[3];
  EXPECT_NE(said[4].find("subscribe"), std::string::npos) << said[4];
  EXPECT_TRUE(server.subscribed(0));  // the one good subscription stands
  EXPECT_EQ(server.counters().refused, 5u);
}

TEST(FoxgloveServer, AClientWithoutTheSubprotocolIsRefused) {
  ServerOptions o;
  o.port = 0;
  Server server(o);
  Client c(server.port(), false);
  ASSERT_TRUE(c.wait([&] { return c.failed_ || c.open_; }));
  EXPECT_TRUE(c.failed_);
  EXPECT_EQ(server.counters().connections, 0u);
}

TEST(FoxgloveServer, AnAddressInUseOrNotAnAddressIsNamed) {
  ServerOptions o;
  o.port = 0;
  Server first(o);
  o.port = first.port();
  try {
    Server second(o);
    FAIL() << "a second server on one port";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("127.0.0.1:" + std::to_string(first.port())), std::string::npos) << e.what();
  }
  o.address = "localhost:1";
  EXPECT_THROW(Server{o}, std::runtime_error);
  o.address = "127.0.0.1";
  o.port = 70000;
  EXPECT_THROW(Server{o}, std::invalid_argument);
}

// A WebSocket client written by hand on a plain socket, which subscribes
// and then never reads again.
class Stalled {
 public:
  explicit Stalled(int port) : socket_(io_) {
    socket_.connect(asio::ip::tcp::endpoint(asio::ip::make_address("127.0.0.1"), std::uint16_t(port)));
    // A small receive buffer, so that the server's sends back up soon.
    socket_.set_option(asio::socket_base::receive_buffer_size(4096));
    const std::string hello =
        "GET / HTTP/1.1\r\nHost: 127.0.0.1\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
        "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n"
        "Sec-WebSocket-Protocol: foxglove.websocket.v1\r\n\r\n";
    asio::write(socket_, asio::buffer(hello));
    asio::streambuf answer;
    asio::read_until(socket_, answer, "\r\n\r\n");
  }
  // One masked text frame (a client's frames are masked).
  void send(const std::string& text) {
    std::string f;
    f.push_back(char(0x81));
    f.push_back(char(0x80 | text.size()));  // under 126 bytes
    const char mask[4] = {1, 2, 3, 4};
    f.append(mask, 4);
    for (std::size_t i = 0; i < text.size(); ++i) f.push_back(char(text[i] ^ mask[i % 4]));
    asio::write(socket_, asio::buffer(f));
  }

 private:
  asio::io_context io_;
  asio::ip::tcp::socket socket_;
};

TEST(FoxgloveServer, AClientThatStopsReadingIsHeldBackAndClosedWhileAReadingOneGetsEverything) {
  ServerOptions o;
  o.port = 0;
  o.client_limit_bytes = 1 << 20;
  o.slow_client_s = 0.5;
  Server server(o);
  server.advertise(channel("mesh"));
  Stalled stalled(server.port());
  stalled.send(R"({"op":"subscribe","subscriptions":[{"id":1,"channelId":0}]})");
  Client reader(server.port());
  ASSERT_TRUE(reader.wait([&] { return reader.texts_.size() >= 2; }));
  reader.send({{"op", "subscribe"}, {"subscriptions", {{{"id", 2}, {"channelId", 0}}}}});
  ASSERT_TRUE(eventually([&] { return server.subscribed(0) && server.counters().clients == 2; }));
  // 200 messages of 100 kB over 2 s: 20 MB, far more than the stalled
  // client's limit and its socket's buffers.
  constexpr int kMessages = 200;
  for (int i = 0; i < kMessages; ++i) {
    server.publish(0, std::uint64_t(i), std::vector<std::uint8_t>(100000, std::uint8_t(i)));
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ASSERT_TRUE(eventually([&] { return server.counters().slow_closed == 1; }))
      << "held back " << server.counters().held_back << ", sent " << server.counters().sent;
  ASSERT_TRUE(reader.wait([&] { return reader.binaries_.size() == kMessages; }));
  const ServerCounters c = server.counters();
  EXPECT_GT(c.held_back, 0u);
  EXPECT_EQ(c.outbox_dropped, 0u);
  std::lock_guard<std::mutex> l(reader.m_);
  for (int i = 0; i < kMessages; ++i) ASSERT_EQ(le(reader.binaries_[std::size_t(i)], 5, 8), std::uint64_t(i));
}

}  // namespace
}  // namespace hcosim::services::foxglove
