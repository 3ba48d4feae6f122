// `tissuebench serve SCENE.yaml`: the live leg. The main thread steps the
// scene (leg::LiveLeg) at real time - or as fast as the engine allows, saying
// so - and every 1/30 s hands a frame to the network thread, which serves the
// viewer page over HTTP and streams the frames over a WebSocket (Boost.Beast,
// from Debian's libboost-dev). The page's messages (viewer/README.md, "Live
// protocol") are checked on the network thread; what is refused is answered
// with an error message and never reaches the simulation.
#include "leg_commands.hpp"

#include "leg/live.hpp"
#include "leg/viewer.hpp"

#include "tbio/json.hpp"

#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/signal_set.hpp>
#include <boost/asio/strand.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <vector>

namespace app {

namespace {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = asio::ip::tcp;
using Clock = std::chrono::steady_clock;

/// Messages from the page longer than this close the connection (Beast);
/// longer than leg::kLiveMessageBytes are refused with a reply.
constexpr size_t kCloseBytes = 65536;
constexpr double kFrameInterval = 1.0 / 30.0;  ///< wall s between frames sent

std::string error_message(const std::string& why) {
  tbio::Json j;
  j["type"] = "error";
  j["message"] = why;
  return j.dump();
}

tbio::Json controls_json(const std::vector<leg::LiveControl>& controls) {
  tbio::Json out = tbio::Json::array();
  for (const leg::LiveControl& c : controls)
    out.push_back({{"id", c.id}, {"label", c.label}, {"kind", c.kind}, {"min", c.min}, {"max", c.max},
                   {"step", c.step}, {"value", c.value}, {"unit", c.unit}});
  return out;
}

class Hub;

/// One WebSocket client: reads the page's messages, writes hello, frames
/// (only the newest waits) and replies, one write at a time.
class WsSession : public std::enable_shared_from_this<WsSession> {
 public:
  WsSession(tcp::socket socket, Hub& hub) : ws_(std::move(socket)), hub_(hub) {}
  void start(http::request<http::string_body> request);
  void send(std::shared_ptr<const std::string> message, bool is_frame);
  void close() {
    beast::error_code ignore;
    beast::get_lowest_layer(ws_).socket().close(ignore);
  }

 private:
  void read();
  void write_next();
  websocket::stream<beast::tcp_stream> ws_;
  Hub& hub_;
  beast::flat_buffer buffer_;
  std::deque<std::shared_ptr<const std::string>> queue_;
  std::shared_ptr<const std::string> frame_;  ///< the newest frame not yet written
  bool writing_ = false;
};

/// What the network thread shares with the simulation: the page, the hello,
/// the sessions, and the commands waiting for the next step.
class Hub {
 public:
  /// `hello` without its controls: hello() adds their current values.
  Hub(asio::io_context& ioc, std::string page, tbio::Json hello, std::vector<leg::LiveControl> controls)
      : ioc_(ioc), page_(std::move(page)), hello_(std::move(hello)), controls_(controls), current_(std::move(controls)) {}
  asio::io_context& ioc() { return ioc_; }
  const std::string& page() const { return page_; }
  /// The hello for a page that connects now: the controls at their current values.
  std::shared_ptr<const std::string> hello() {
    tbio::Json h = hello_;
    std::lock_guard<std::mutex> lock(mutex_);
    h["controls"] = controls_json(current_);
    return std::make_shared<const std::string>(h.dump());
  }
  /// From the simulation thread, after the controls changed.
  void set_current(const std::vector<leg::LiveControl>& controls) {
    std::lock_guard<std::mutex> lock(mutex_);
    current_ = controls;
  }
  /// The controls' ids and ranges (fixed for the run): what messages are checked against.
  const std::vector<leg::LiveControl>& controls() const { return controls_; }

  void join(const std::shared_ptr<WsSession>& s) {
    sessions_.insert(s);
    clients_ = static_cast<int>(sessions_.size());
  }
  void leave(const std::shared_ptr<WsSession>& s) {
    sessions_.erase(s);
    clients_ = static_cast<int>(sessions_.size());
  }
  int clients() const { return clients_; }
  /// From the simulation thread: sends to every client on the network thread.
  void broadcast(std::string message, bool is_frame) {
    auto m = std::make_shared<const std::string>(std::move(message));
    asio::post(ioc_, [this, m, is_frame] {
      for (const auto& s : sessions_) s->send(m, is_frame);
    });
  }
  void push(const leg::LiveCommand& c) {
    std::lock_guard<std::mutex> lock(mutex_);
    commands_.push_back(c);
  }
  std::vector<leg::LiveCommand> take() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<leg::LiveCommand> out;
    out.swap(commands_);
    return out;
  }
  void close_all() {
    for (const auto& s : sessions_) s->close();
  }

 private:
  asio::io_context& ioc_;
  std::string page_;
  tbio::Json hello_;
  const std::vector<leg::LiveControl> controls_;
  std::vector<leg::LiveControl> current_;  // guarded by mutex_
  std::set<std::shared_ptr<WsSession>> sessions_;  // network thread only
  std::atomic<int> clients_{0};
  std::mutex mutex_;
  std::vector<leg::LiveCommand> commands_;
};

void WsSession::start(http::request<http::string_body> request) {
  ws_.read_message_max(kCloseBytes);
  ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
  ws_.async_accept(request, [self = shared_from_this()](beast::error_code ec) {
    if (ec) return;
    self->hub_.join(self);
    self->send(self->hub_.hello(), false);
    self->read();
  });
}

void WsSession::read() {
  ws_.async_read(buffer_, [self = shared_from_this()](beast::error_code ec, size_t) {
    if (ec) {
      self->hub_.leave(self);
      return;
    }
    const std::string text = beast::buffers_to_string(self->buffer_.data());
    self->buffer_.consume(self->buffer_.size());
    leg::LiveCommand cmd;
    const std::string why = leg::parse_live_message(text, self->hub_.controls(), cmd);
    if (why.empty())
      self->hub_.push(cmd);
    else
      self->send(std::make_shared<const std::string>(error_message(why)), false);
    self->read();
  });
}

void WsSession::send(std::shared_ptr<const std::string> message, bool is_frame) {
  if (is_frame)
    frame_ = std::move(message);  // a slow page skips frames, never falls behind
  else
    queue_.push_back(std::move(message));
  if (!writing_) write_next();
}

void WsSession::write_next() {
  std::shared_ptr<const std::string> m;
  if (!queue_.empty()) {
    m = queue_.front();
    queue_.pop_front();
  } else if (frame_) {
    m = std::move(frame_);
    frame_.reset();
  }
  if (!m) {
    writing_ = false;
    return;
  }
  writing_ = true;
  ws_.text(true);
  ws_.async_write(asio::buffer(*m), [self = shared_from_this(), m](beast::error_code ec, size_t) {
    if (ec) {
      self->writing_ = false;
      self->hub_.leave(self);
      return;
    }
    self->write_next();
  });
}

/// One HTTP connection: the page at "/", the WebSocket at "/ws", 404 else.
class HttpSession : public std::enable_shared_from_this<HttpSession> {
 public:
  HttpSession(tcp::socket socket, Hub& hub) : stream_(std::move(socket)), hub_(hub) {}
  void start() {
    parser_.emplace();
    parser_->header_limit(8192);
    parser_->body_limit(8192);
    stream_.expires_after(std::chrono::seconds(30));
    http::async_read(stream_, buffer_, *parser_, [self = shared_from_this()](beast::error_code ec, size_t) {
      if (!ec) self->answer(self->parser_->release());
    });
  }

 private:
  void answer(http::request<http::string_body> req) {
    const std::string target(req.target());
    if (websocket::is_upgrade(req)) {
      // Only pages this server gave out may connect: a page of another origin
      // (any other web site open in the browser) is refused.
      const auto origin = req.find(http::field::origin);
      const std::string host(req[http::field::host]);
      const bool same_origin = origin == req.end() || std::string(origin->value()) == "http://" + host;
      if (target == "/ws" && same_origin) {
        stream_.expires_never();
        std::make_shared<WsSession>(stream_.release_socket(), hub_)->start(std::move(req));
        return;
      }
      return reply(req, http::status::forbidden, "text/plain", "refused: WebSocket only at /ws from this server's page\n");
    }
    if (req.method() != http::verb::get && req.method() != http::verb::head)
      return reply(req, http::status::method_not_allowed, "text/plain", "only GET\n");
    if (target == "/" || target == "/index.html") return reply(req, http::status::ok, "text/html; charset=utf-8", hub_.page());
    reply(req, http::status::not_found, "text/plain", "not found: the page is at /\n");
  }

  void reply(const http::request<http::string_body>& req, http::status status, const char* type,
             const std::string& body) {
    auto res = std::make_shared<http::response<http::string_body>>(status, req.version());
    res->set(http::field::server, "tissuebench");
    res->set(http::field::content_type, type);
    res->set(http::field::cache_control, "no-store");
    res->keep_alive(false);
    if (req.method() != http::verb::head) res->body() = body;
    res->prepare_payload();
    http::async_write(stream_, *res, [self = shared_from_this(), res](beast::error_code, size_t) {
      beast::error_code ignore;
      self->stream_.socket().shutdown(tcp::socket::shutdown_send, ignore);
    });
  }

  beast::tcp_stream stream_;
  Hub& hub_;
  beast::flat_buffer buffer_;
  std::optional<http::request_parser<http::string_body>> parser_;
};

void accept(tcp::acceptor& acceptor, Hub& hub) {
  acceptor.async_accept(asio::make_strand(hub.ioc()), [&acceptor, &hub](beast::error_code ec, tcp::socket socket) {
    if (!acceptor.is_open()) return;
    if (!ec) std::make_shared<HttpSession>(std::move(socket), hub)->start();
    accept(acceptor, hub);
  });
}

tbio::Json hello_message(const leg::LiveLeg& live) {
  tbio::Json h;
  h["type"] = "hello";
  h["format"] = "tissuebench-live/1";
  h["scene"] = live.scene().name;
  h["dt"] = live.scene().dt;
  const leg::Instruments& in = live.instruments();
  h["meshes"] = tbio::Json::array();
  h["meshes"].push_back(leg::viewer_mesh("skin", in.skin->vertices, in.skin->triangles));
  if (in.bones.num_vertices() > 0) h["meshes"].push_back(leg::viewer_mesh("bones", in.bones.vertices, in.bones.triangles));
  if (in.obstacles.num_vertices() > 0)
    h["meshes"].push_back(leg::viewer_mesh("obstacles", in.obstacles.vertices, in.obstacles.triangles));
  h["controls"] = controls_json(live.controls());
  h["series"] = tbio::Json::array();
  for (const leg::Sensor& s : live.sensors())
    if (s.name != "time") h["series"].push_back({{"name", s.name}, {"unit", s.unit}});
  return h;
}

std::string frame_message(leg::LiveLeg& live, double speed, bool slower) {
  const leg::Frame& f = live.frame();
  tbio::Json m;
  m["type"] = "frame";
  m["t"] = live.time();
  m["real_time_factor"] = speed;
  m["slower_than_real_time"] = slower;
  m["knee_angle"] = f.state->knee.angle * 180.0 / M_PI;
  tbio::Json values = tbio::Json::object();
  for (const leg::Sensor& s : live.sensors()) {
    if (s.name == "time") continue;
    const double v = s.read(f);
    values[s.name] = std::isfinite(v) ? tbio::Json(v) : tbio::Json(nullptr);
  }
  m["values"] = std::move(values);
  m["positions"] = tbio::Json::array();
  m["positions"].push_back({{"name", "skin"}, {"b64", leg::positions_base64(f.skin_x)}});
  if (f.bones_x.cols() > 0) m["positions"].push_back({{"name", "bones"}, {"b64", leg::positions_base64(f.bones_x)}});
  if (f.obstacles_x.cols() > 0)
    m["positions"].push_back({{"name", "obstacles"}, {"b64", leg::positions_base64(f.obstacles_x)}});
  return m.dump();
}

std::string status_message(const std::string& text, bool failed) {
  tbio::Json m;
  m["type"] = "status";
  m["message"] = text;
  m["failed"] = failed;
  return m.dump();
}

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

/// Real-time pacing: the simulated clock follows the wall clock from a base;
/// when the engine cannot keep up, the debt is dropped (never more than
/// kMaxLag) and the speed measured over each second says so.
class Pacer {
 public:
  static constexpr double kMaxLag = 0.2;  ///< s of simulated time the engine may fall behind
  explicit Pacer(double t) { restart(t); }
  void restart(double t) {
    base_ = Clock::now();
    base_t_ = t;
  }
  double target() const { return base_t_ + seconds_since(base_); }
  /// After a loop: drops a debt over kMaxLag; adds the loop's simulated and
  /// wall seconds. Returns true when a new second's speed was measured.
  bool measure(double t, double simulated, double wall) {
    if (target() - t > kMaxLag) restart(t);
    window_sim_ += simulated;
    window_wall_ += wall;
    if (window_wall_ < 1.0) return false;
    speed_ = window_sim_ / window_wall_;
    window_sim_ = window_wall_ = 0.0;
    return true;
  }
  double speed() const { return speed_; }
  bool slower() const { return speed_ < 0.95; }

 private:
  Clock::time_point base_;
  double base_t_ = 0.0, window_sim_ = 0.0, window_wall_ = 0.0, speed_ = 1.0;
};

/// Opens the listening socket; throws msd::Error naming --bind or --port.
void listen_on(tcp::acceptor& acceptor, const std::string& bind, int port) {
  beast::error_code ec;
  const auto address = asio::ip::make_address(bind, ec);
  if (ec) throw msd::Error("--bind " + bind + ": not an IP address");
  const tcp::endpoint endpoint(address, static_cast<unsigned short>(port));
  acceptor.open(endpoint.protocol(), ec);
  if (!ec) acceptor.set_option(asio::socket_base::reuse_address(true), ec);
  if (!ec) acceptor.bind(endpoint, ec);
  if (!ec) acceptor.listen(asio::socket_base::max_listen_connections, ec);
  if (ec)
    throw msd::Error("--port " + std::to_string(port) + ": cannot listen on " + bind + ":" + std::to_string(port) +
                     " (" + ec.message() + ")");
}

/// The page's commands since the last loop, applied (checked on arrival).
void apply_commands(leg::LiveLeg& live, Hub& hub, Pacer& pacer) {
  for (const leg::LiveCommand& c : hub.take()) {
    if (c.reset) {
      live.reset();
      pacer.restart(live.time());
      hub.broadcast(status_message("reset to the scene's start", false), false);
    } else {
      live.set(c.id, c.value);
      hub.set_current(live.controls());
    }
  }
}

/// Steps towards the pacer's target for at most one frame interval of wall
/// time. A blow-up resets the leg with the scene's own controls (the page's
/// sliders follow the new hello), so one bad setting cannot blow it up again
/// and again. Returns whether it stepped at all.
bool advance(leg::LiveLeg& live, Hub& hub, Pacer& pacer, long chunk) {
  const auto start = Clock::now();
  bool stepped = false;
  while (seconds_since(start) < kFrameInterval && live.time() < pacer.target()) {
    if (!live.step(chunk)) {
      live.reset_controls();
      live.reset();
      hub.broadcast(status_message("the simulation failed and was reset with the scene's controls: " + live.failure(),
                                   true),
                    false);
      hub.set_current(live.controls());
      hub.broadcast(*hub.hello(), false);
      std::fprintf(stderr, "serve: %s (reset)\n", live.failure().c_str());
      pacer.restart(live.time());
      return true;
    }
    stepped = true;
  }
  return stepped;
}

}  // namespace

int cmd_serve(const ServeArgs& args) {
  const std::string file =
      args.scene.empty() ? std::string(TISSUEBENCH_DATA_DIR) + "/scenes/hamstrings.yaml" : args.scene;
  leg::LegScene scene = leg::read_leg_scene(file);  // bad input: msd::Error, exit 2, before any port is opened
  if (args.threads > 0) scene.model.threads = args.threads;
  leg::LiveLeg live(std::move(scene));
  const double dt = live.scene().dt;

  asio::io_context ioc;
  tcp::acceptor acceptor(ioc);
  listen_on(acceptor, args.bind, args.port);
  tbio::Json config;
  config["mode"] = "live";
  config["ws"] = "/ws";
  Hub hub(ioc, leg::viewer_page(config), hello_message(live), live.controls());
  std::atomic<bool> stop{false};
  asio::signal_set signals(ioc, SIGINT, SIGTERM);
  signals.async_wait([&](beast::error_code, int) { stop = true; });
  accept(acceptor, hub);
  std::thread network([&] { ioc.run(); });

  const bool v6 = acceptor.local_endpoint().address().is_v6();
  std::printf("tissuebench serve: http://%s%s%s:%u/  (scene %s, dt %g s; Ctrl-C stops)\n", v6 ? "[" : "",
              args.bind.c_str(), v6 ? "]" : "", acceptor.local_endpoint().port(), live.scene().name.c_str(), dt);
  std::fflush(stdout);

  const auto started = Clock::now();
  Pacer pacer(live.time());
  auto last_frame = Clock::now() - std::chrono::seconds(1), last_note = Clock::now();
  const long chunk = std::max(1L, std::lround(0.002 / dt));  // steps between looks at the clock
  while (!stop && !(args.seconds > 0.0 && seconds_since(started) >= args.seconds)) {
    apply_commands(live, hub, pacer);
    const auto loop_start = Clock::now();
    const double t0 = live.time();
    if (!advance(live, hub, pacer, chunk)) {  // ahead of the wall clock: wait for the next frame
      const auto next = last_frame + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(kFrameInterval));
      if (Clock::now() < next) std::this_thread::sleep_until(next);
    }
    if (pacer.measure(live.time(), std::max(0.0, live.time() - t0), seconds_since(loop_start)) && pacer.slower() &&
        seconds_since(last_note) > 10.0) {
      std::fprintf(stderr, "serve: %.2fx real time: the engine is slower than real time on this machine\n",
                   pacer.speed());
      last_note = Clock::now();
    }
    if (seconds_since(last_frame) >= kFrameInterval) {
      last_frame = Clock::now();
      if (hub.clients() > 0) hub.broadcast(frame_message(live, pacer.speed(), pacer.slower()), true);
    }
  }
  asio::post(ioc, [&] {
    beast::error_code ignore;
    acceptor.close(ignore);
    signals.cancel(ignore);
    hub.close_all();
  });
  ioc.stop();
  network.join();
  std::printf("tissuebench serve: stopped after %.1f s simulated\n", live.time());
  return 0;
}

}  // namespace app
