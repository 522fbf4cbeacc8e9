#include "services/foxglove/client.h"

#include <mutex>
#include <thread>

#include <nlohmann/json.hpp>
#include <websocketpp/client.hpp>
#include <websocketpp/config/asio_no_tls_client.hpp>

#include "services/foxglove/server.h"

namespace hcosim::services::foxglove {

using WsClient = websocketpp::client<websocketpp::config::asio_client>;

struct Client::Impl {
  WsClient ws;
  WsClient::connection_ptr con;
  std::thread thread;
  mutable std::mutex m;
  ClientCounts counts;
  std::map<std::uint32_t, std::string> topic_of;  // subscription id (the channel id) -> topic

  void on_message(const WsClient::message_ptr& msg) {
    const std::string& p = msg->get_payload();
    if (msg->get_opcode() == websocketpp::frame::opcode::binary) {
      if (p.size() < 13 || p[0] != 1) return;  // time frames and the like
      std::uint32_t sub = 0;
      for (int i = 0; i < 4; ++i) sub |= std::uint32_t(std::uint8_t(p[1 + i])) << (8 * i);
      std::lock_guard<std::mutex> l(m);
      ++counts.messages, counts.bytes += p.size() - 13;
      ++counts.per_topic[topic_of[sub]];
      return;
    }
    const nlohmann::json j = nlohmann::json::parse(p, nullptr, false);
    if (j.is_discarded() || !j.is_object()) return;
    if (j.value("op", "") == "status") {
      std::lock_guard<std::mutex> l(m);
      ++counts.statuses;
    } else if (j.value("op", "") == "advertise") {
      nlohmann::json subs = nlohmann::json::array();
      {
        std::lock_guard<std::mutex> l(m);
        for (const nlohmann::json& c : j["channels"]) {
          const std::uint32_t id = c["id"];
          topic_of[id] = c["topic"];
          subs.push_back({{"id", id}, {"channelId", id}});
          ++counts.channels;
        }
      }
      con->send(nlohmann::json{{"op", "subscribe"}, {"subscriptions", subs}}.dump(), websocketpp::frame::opcode::text);
    }
  }
};

Client::Client(const std::string& address, int port) : impl_(std::make_unique<Impl>()) {
  Impl& c = *impl_;
  c.ws.clear_access_channels(websocketpp::log::alevel::all);
  c.ws.clear_error_channels(websocketpp::log::elevel::all);
  c.ws.init_asio();
  c.ws.set_open_handler([&c](websocketpp::connection_hdl) {
    std::lock_guard<std::mutex> l(c.m);
    c.counts.open = true;
  });
  c.ws.set_close_handler([&c](websocketpp::connection_hdl) {
    std::lock_guard<std::mutex> l(c.m);
    c.counts.open = false;
  });
  c.ws.set_message_handler([&c](websocketpp::connection_hdl, WsClient::message_ptr m) { c.on_message(m); });
  websocketpp::lib::error_code ec;
  c.con = c.ws.get_connection("ws://" + address + ":" + std::to_string(port), ec);
  if (ec)
    throw std::runtime_error("foxglove client: ws://" + address + ":" + std::to_string(port) + ": " + ec.message());
  c.con->add_subprotocol(Server::kSubprotocol);
  c.ws.connect(c.con);
  c.thread = std::thread([&c] { c.ws.run(); });
}

Client::~Client() {
  Impl& c = *impl_;
  websocketpp::lib::error_code ec;
  c.con->close(websocketpp::close::status::normal, "", ec);
  c.ws.stop();
  c.thread.join();
}

ClientCounts Client::counts() const {
  std::lock_guard<std::mutex> l(impl_->m);
  return impl_->counts;
}

}  // namespace hcosim::services::foxglove
