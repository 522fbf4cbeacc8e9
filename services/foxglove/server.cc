#include "services/foxglove/server.h"

#include <pthread.h>

#include <chrono>
#include <deque>
#include <map>
#include <mutex>
#include <stdexcept>
#include <thread>

#include <nlohmann/json.hpp>
#include <websocketpp/config/asio_no_tls.hpp>
#include <websocketpp/server.hpp>

namespace hcosim::services::foxglove {

namespace {

using WsServer = websocketpp::server<websocketpp::config::asio>;
using Hdl = websocketpp::connection_hdl;
using json = nlohmann::json;

// The protocol's binary opcodes, server to client.
constexpr std::uint8_t kMessageData = 1;
constexpr std::uint8_t kTimeData = 2;
// A client's requests are small JSON texts.
constexpr std::size_t kMaxRequestBytes = 1 << 16;
// How often the socket thread sends what waits: well under a frame of
// Foxglove's panels (60 Hz).
constexpr std::chrono::milliseconds kFlushPeriod{10};

std::int64_t now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

void put_le(char* out, std::uint64_t v, int bytes) {
  for (int i = 0; i < bytes; ++i) out[i] = char(std::uint8_t(v >> (8 * i)));
}

// A binary websocket frame of `payload`, prepared here (header made, no
// masking from a server) so that websocketpp sends the bytes as they are
// instead of copying them twice into messages of its own.
WsServer::message_ptr binary_frame(std::string payload) {
  const auto op = websocketpp::frame::opcode::binary;
  auto msg = std::make_shared<websocketpp::config::asio::message_type>(nullptr, op, 0);
  const websocketpp::frame::basic_header head(op, payload.size(), true, false);
  msg->set_header(websocketpp::frame::prepare_header(head, websocketpp::frame::extended_header(payload.size())));
  msg->get_raw_payload() = std::move(payload);
  msg->set_prepared(true);
  return msg;
}

json channel_json(std::uint32_t id, const Channel& c) {
  return {{"id", id},
          {"topic", c.topic},
          {"encoding", c.encoding},
          {"schemaName", c.schema_name},
          {"schema", c.schema},
          {"schemaEncoding", c.schema_encoding}};
}

}  // namespace

struct Server::Impl {
  // What waits for the socket thread: a message, the clock, or a channel.
  struct Out {
    enum Kind { kMessage, kTime, kAdvertise } kind = kMessage;
    std::uint32_t channel = 0;
    std::uint64_t time_ns = 0;
    std::string framed;  // kHeadroom bytes, then the message's data
    Channel advertised;
  };
  struct Client {
    std::map<std::uint32_t, std::uint32_t> channel_of;  // subscription id -> channel
    std::map<std::uint32_t, std::uint32_t> sub_of;      // channel -> subscription id
    std::int64_t over_since_ns = 0;                     // 0: within its limit
  };

  ServerOptions o;
  WsServer ws;
  std::thread thread;
  int port = 0;

  // The socket thread's own.
  std::map<Hdl, Client, std::owner_less<Hdl>> clients;
  std::vector<Channel> channels;                                       // by id
  std::vector<std::pair<WsServer::connection_ptr, std::uint32_t>> to;  // flush(): a message's clients, subscriptions

  // Any thread.
  std::array<std::atomic<std::uint32_t>, kMaxChannels> subscribers{};
  std::mutex m;  // outbox, next_channel
  std::deque<Out> outbox;
  std::size_t outbox_bytes = 0;
  std::unique_ptr<asio::steady_timer> flush_timer;
  std::mutex hook_m;           // hook
  std::function<void()> hook;  // every_flush()
  std::uint32_t next_channel = 0;
  std::atomic<std::uint64_t> connections{0}, sent{0}, bytes{0}, held_back{0}, outbox_dropped{0}, slow_closed{0},
      refused{0}, n_clients{0};

  // With `m` held.
  void enqueue_locked(Out out) {
    if (out.kind == Out::kMessage && outbox_bytes + out.framed.size() > o.outbox_limit_bytes) {
      ++outbox_dropped;
      return;
    }
    outbox_bytes += out.framed.size();
    outbox.push_back(std::move(out));
  }

  // The socket thread sends what waits every kFlushPeriod, so that a
  // burst of messages costs it one wake-up, not one each.
  void flush_every_period() {
    {
      std::lock_guard<std::mutex> l(hook_m);
      if (hook) hook();
    }
    flush();
    flush_timer->expires_after(kFlushPeriod);
    flush_timer->async_wait([this](const asio::error_code& ec) {
      if (!ec) flush_every_period();
    });
  }
  void enqueue(Out out) {
    std::lock_guard<std::mutex> l(m);
    enqueue_locked(std::move(out));
  }

  void send_text(Hdl h, const json& j) {
    websocketpp::lib::error_code ec;
    ws.send(h, j.dump(), websocketpp::frame::opcode::text, ec);
  }

  void status(Hdl h, int level, const std::string& message) {
    if (level == 2) ++refused;
    send_text(h, {{"op", "status"}, {"level", level}, {"message", message}});
  }

  // Socket thread: sends what waits.
  void flush() {
    std::deque<Out> batch;
    {
      std::lock_guard<std::mutex> l(m);
      batch.swap(outbox);
      outbox_bytes = 0;
    }
    const std::int64_t now = now_ns();
    for (Out& out : batch) {
      if (out.kind == Out::kAdvertise) {
        // Ids are given in the outbox's order, so an id is its index here.
        channels.push_back(out.advertised);
        const json j = {{"op", "advertise"}, {"channels", {channel_json(out.channel, out.advertised)}}};
        for (auto& c : clients) send_text(c.first, j);
        continue;
      }
      // The clients it goes to: the last one takes the bytes, the others a copy.
      to.clear();
      for (auto& [h, c] : clients) {
        std::uint32_t sub = 0;
        if (out.kind == Out::kMessage) {
          const auto s = c.sub_of.find(out.channel);
          if (s == c.sub_of.end()) continue;
          sub = s->second;
        }
        websocketpp::lib::error_code ec;
        const WsServer::connection_ptr con = ws.get_con_from_hdl(h, ec);
        if (ec || con->get_state() != websocketpp::session::state::open || !within_limit(c, con, out.kind, now))
          continue;
        to.emplace_back(con, sub);
      }
      if (out.kind == Out::kTime) out.framed.assign(9, '\0');
      for (std::size_t i = 0; i < to.size(); ++i) {
        const auto& [con, sub] = to[i];
        std::string frame = i + 1 == to.size() ? std::move(out.framed) : out.framed;
        if (out.kind == Out::kMessage) {
          frame[0] = char(kMessageData);
          put_le(&frame[1], sub, 4);
          put_le(&frame[5], out.time_ns, 8);
          ++sent;
        } else {
          frame[0] = char(kTimeData);
          put_le(&frame[1], out.time_ns, 8);
        }
        bytes += frame.size();
        con->send(binary_frame(std::move(frame)));
      }
    }
  }

  // Whether a client may be sent more now; one over its limit for too long is closed.
  bool within_limit(Client& c, const WsServer::connection_ptr& con, Out::Kind kind, std::int64_t now) {
    const std::size_t unsent = con->get_buffered_amount();
    // Hysteresis: a client counts as caught up only under half its
    // limit, so one that drains a trickle into its kernel's growing
    // buffer, hovering at the limit, is still closed.
    if (unsent < o.client_limit_bytes / 2) c.over_since_ns = 0;
    if (unsent <= o.client_limit_bytes) return true;
    if (kind == Out::kMessage) ++held_back;
    if (c.over_since_ns == 0) c.over_since_ns = now;
    if (now - c.over_since_ns > std::int64_t(o.slow_client_s * 1e9)) {
      ++slow_closed;
      c.over_since_ns = INT64_MAX / 2;  // closed once
      websocketpp::lib::error_code ec;
      con->close(websocketpp::close::status::policy_violation, "too slow: not reading its messages", ec);
    }
    return false;
  }

  void on_open(Hdl h) {
    ++connections, ++n_clients;
    clients[h];
    send_text(h, {{"op", "serverInfo"},
                  {"name", o.name},
                  {"capabilities", {"time"}},
                  {"supportedEncodings", json::array()},
                  {"metadata", json::object()},
                  {"sessionId", std::to_string(now_ns())}});
    json list = json::array();
    for (std::size_t i = 0; i < channels.size(); ++i) list.push_back(channel_json(std::uint32_t(i), channels[i]));
    if (!list.empty()) send_text(h, {{"op", "advertise"}, {"channels", list}});
  }

  void on_close(Hdl h) {
    const auto it = clients.find(h);
    if (it == clients.end()) return;
    for (const auto& [channel, sub] : it->second.sub_of) --subscribers[channel];
    clients.erase(it);
    --n_clients;
  }

  void on_message(Hdl h, const WsServer::message_ptr& msg) {
    const auto it = clients.find(h);
    if (it == clients.end()) return;
    Client& c = it->second;
    if (msg->get_opcode() != websocketpp::frame::opcode::text)
      return status(h, 2, "this server takes no client messages (no clientPublish capability)");
    const json j = json::parse(msg->get_payload(), nullptr, false);
    if (j.is_discarded() || !j.is_object() || !j.contains("op") || !j["op"].is_string())
      return status(h, 2, "not a JSON object with an op: " + msg->get_payload().substr(0, 80));
    const std::string op = j["op"];
    try {
      if (op == "subscribe") {
        for (const json& s : j.at("subscriptions")) {
          const std::uint32_t id = s.at("id").get<std::uint32_t>(), channel = s.at("channelId").get<std::uint32_t>();
          if (channel >= channels.size())
            status(h, 2, "subscribe: no channel " + std::to_string(channel));
          else if (c.channel_of.count(id))
            status(h, 2, "subscribe: subscription id " + std::to_string(id) + " is in use");
          else if (c.sub_of.count(channel))
            status(h, 2, "subscribe: channel " + std::to_string(channel) + " is already subscribed");
          else
            c.channel_of[id] = channel, c.sub_of[channel] = id, ++subscribers[channel];
        }
      } else if (op == "unsubscribe") {
        for (const json& s : j.at("subscriptionIds")) {
          const std::uint32_t id = s.get<std::uint32_t>();
          const auto sub = c.channel_of.find(id);
          if (sub == c.channel_of.end()) {
            status(h, 2, "unsubscribe: no subscription " + std::to_string(id));
            continue;
          }
          --subscribers[sub->second];
          c.sub_of.erase(sub->second);
          c.channel_of.erase(sub);
        }
      } else {
        status(h, 1, "op '" + op + "' is not supported by this server");
      }
    } catch (const json::exception& e) {
      status(h, 2, op + ": " + e.what());
    }
  }
};

Server::Server(ServerOptions o) : impl_(std::make_unique<Impl>()) {
  if (o.port < 0 || o.port > 65535) throw std::invalid_argument("port " + std::to_string(o.port) + " is not 0..65535");
  if (!(o.slow_client_s > 0)) throw std::invalid_argument("slow_client_s must be > 0");
  if (o.socket_buffer_bytes < 4096) throw std::invalid_argument("socket_buffer_bytes must be at least 4096");
  Impl& s = *impl_;
  s.o = std::move(o);
  const std::string where = s.o.address + ":" + std::to_string(s.o.port);
  asio::error_code aec;
  const asio::ip::address address = asio::ip::make_address(s.o.address, aec);
  if (aec) throw std::runtime_error("foxglove: '" + s.o.address + "' is not an IP address");
  s.ws.clear_access_channels(websocketpp::log::alevel::all);
  s.ws.clear_error_channels(websocketpp::log::elevel::all);
  s.ws.init_asio();
  s.ws.set_reuse_addr(true);
  s.ws.set_max_message_size(kMaxRequestBytes);
  s.ws.set_socket_init_handler([&s](Hdl, asio::ip::tcp::socket& sock) {
    asio::error_code ec;
    sock.set_option(asio::ip::tcp::no_delay(true), ec);
    sock.set_option(asio::socket_base::send_buffer_size(s.o.socket_buffer_bytes), ec);
  });
  s.ws.set_validate_handler([&s](Hdl h) {
    const WsServer::connection_ptr con = s.ws.get_con_from_hdl(h);
    for (const std::string& p : con->get_requested_subprotocols())
      if (p == kSubprotocol) return con->select_subprotocol(p), true;
    return false;
  });
  s.ws.set_open_handler([&s](Hdl h) { s.on_open(h); });
  s.ws.set_close_handler([&s](Hdl h) { s.on_close(h); });
  s.ws.set_fail_handler([&s](Hdl h) { s.on_close(h); });
  s.ws.set_message_handler([&s](Hdl h, WsServer::message_ptr m) { s.on_message(h, m); });
  websocketpp::lib::error_code ec;
  s.ws.listen(asio::ip::tcp::endpoint(address, std::uint16_t(s.o.port)), ec);
  if (!ec) s.ws.start_accept(ec);
  if (ec) throw std::runtime_error("foxglove: cannot listen on " + where + ": " + ec.message());
  s.port = s.ws.get_local_endpoint(aec).port();
  s.flush_timer = std::make_unique<asio::steady_timer>(s.ws.get_io_service());
  s.flush_every_period();
  s.thread = std::thread([&s] {
    pthread_setname_np(pthread_self(), "fox_socket");
    s.ws.run();
  });
}

Server::~Server() {
  Impl& s = *impl_;
  asio::post(s.ws.get_io_service(), [&s] {
    websocketpp::lib::error_code ec;
    s.flush_timer->cancel();
    s.ws.stop_listening(ec);
    for (auto& c : s.clients) s.ws.close(c.first, websocketpp::close::status::going_away, "server stopping", ec);
  });
  // Clients that answer the close let run() return; those that do not are cut.
  for (int i = 0; i < 50 && !s.ws.stopped() && s.n_clients > 0; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  s.ws.stop();
  s.thread.join();
}

int Server::port() const { return impl_->port; }
const std::string& Server::address() const { return impl_->o.address; }

std::uint32_t Server::advertise(const Channel& c) {
  Impl& s = *impl_;
  std::lock_guard<std::mutex> l(s.m);
  if (s.next_channel >= kMaxChannels) throw std::length_error("foxglove: more than 256 channels");
  const std::uint32_t id = s.next_channel++;
  Impl::Out out;
  out.kind = Impl::Out::kAdvertise;
  out.channel = id;
  out.advertised = c;
  s.enqueue_locked(std::move(out));
  // At once, not at the next period: a client connecting now sees it in its first advertise.
  asio::post(s.ws.get_io_service(), [&s] { s.flush(); });
  return id;
}

bool Server::subscribed(std::uint32_t channel) const {
  return channel < kMaxChannels && impl_->subscribers[channel].load(std::memory_order_relaxed) > 0;
}

void Server::publish(std::uint32_t channel, std::uint64_t time_ns, const std::vector<std::uint8_t>& data) {
  std::string framed(kHeadroom, '\0');
  framed.append(data.begin(), data.end());
  publish_framed(channel, time_ns, std::move(framed));
}

void Server::publish_framed(std::uint32_t channel, std::uint64_t time_ns, std::string framed) {
  if (framed.size() < kHeadroom) throw std::invalid_argument("foxglove: a framed message needs its 13 free bytes");
  Impl::Out out;
  out.channel = channel;
  out.time_ns = time_ns;
  out.framed = std::move(framed);
  impl_->enqueue(std::move(out));
}

void Server::time(std::uint64_t time_ns) {
  Impl::Out out;
  out.kind = Impl::Out::kTime;
  out.time_ns = time_ns;
  impl_->enqueue(std::move(out));
}

void Server::every_flush(std::function<void()> f) {
  std::lock_guard<std::mutex> l(impl_->hook_m);
  impl_->hook = std::move(f);
}

ServerCounters Server::counters() const {
  const Impl& s = *impl_;
  ServerCounters c;
  c.clients = s.n_clients, c.connections = s.connections, c.sent = s.sent, c.bytes = s.bytes;
  c.held_back = s.held_back, c.outbox_dropped = s.outbox_dropped, c.slow_closed = s.slow_closed;
  c.refused = s.refused;
  return c;
}

}  // namespace hcosim::services::foxglove
