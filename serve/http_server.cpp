#include "serve/http_server.h"

#include <spdlog/spdlog.h>

#include <array>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/beast/core/error.hpp>
#include <boost/beast/core/flat_buffer.hpp>
#include <boost/beast/core/tcp_stream.hpp>
#include <boost/beast/http/error.hpp>
#include <boost/beast/http/read.hpp>
#include <boost/beast/http/string_body.hpp>
#include <boost/beast/http/write.hpp>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <exception>
#include <map>
#include <mutex>
#include <optional>
#include <thread>

#include "common/error.h"
#include "util/text.h"

namespace napkin::serve {
namespace {

namespace net = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
using Tcp = net::ip::tcp;
using Clock = std::chrono::steady_clock;

// docs/serve.md "Safety": what a request and a connection may take.
// A request's header (and its body, if any) must have arrived complete this long after the
// connection opened or after the previous answer on it was sent: a total deadline, however the
// bytes trickle in. It is also how long an idle kept-alive connection stays open.
constexpr std::chrono::seconds kRequestDeadline{5};
constexpr std::size_t kMaxHeaderBytes = std::size_t{64} * 1024;  // the request line and every field
constexpr std::size_t kMaxTargetBytes = 8192;                    // the request target (414)
constexpr std::size_t kMaxHeaderFields = 100;                    // 431
constexpr std::size_t kMaxBodyBytes = std::size_t{64} * 1024;    // GET only: a body is never needed
// Bytes read ahead of the request being parsed (pipelined requests wait in the kernel beyond).
constexpr std::size_t kReadBufferBytes = kMaxHeaderBytes + kMaxBodyBytes;
// Open connections, idle ones included; one beyond is answered 503 and closed. Each holds a
// descriptor and at most one request and one answer in memory.
constexpr std::size_t kMaxConnections = 256;
// Connections beyond the cap being answered 503 at one time; beyond these they are closed unanswered.
constexpr std::size_t kMaxRefusedConnections = 64;
// An answer is written within 30 s plus 1 s per 64 KiB (a slow client reading a large report).
constexpr std::chrono::seconds kWriteAllowance{30};
constexpr std::size_t kWriteBytesPerSecond = std::size_t{64} * 1024;
// After a final answer the connection's further bytes are read and dropped this long, so that
// closing it with unread bytes (a request it sent on) does not reset the answer away.
constexpr std::chrono::seconds kLingerTime{1};
// After Stop(): the answers in progress get this long, then every connection is closed; request
// threads still working at kStopThreadsTime are left to the process's exit.
constexpr std::chrono::milliseconds kStopGrace{500};
constexpr std::chrono::milliseconds kStopThreadsTime{1000};
// After a failed accept (out of descriptors): the next try.
constexpr std::chrono::milliseconds kAcceptRetry{100};

// A parser's error that says what is wrong with the request, not that the client went.
bool IsMalformedRequest(const beast::error_code& error) {
  return error.category() == make_error_code(http::error::bad_method).category() &&
         error != http::error::end_of_stream && error != http::error::partial_message &&
         error != http::error::short_read;
}

std::chrono::seconds WriteDeadline(std::size_t bytes) {
  return kWriteAllowance + std::chrono::seconds(bytes / kWriteBytesPerSecond);
}

}  // namespace

std::vector<std::string_view> HttpRequest::Values(std::string_view name) const {
  std::vector<std::string_view> values;
  for (const auto& [field, value] : fields)
    if (util::EqualsIgnoreCase(field, name)) values.emplace_back(value);
  return values;
}

namespace detail {

// The request threads: a request is queued once it has arrived complete, at most one per
// connection (the next is read after its answer), so the queue is bounded by kMaxConnections.
class RequestThreads {
 public:
  explicit RequestThreads(int count) : ended_(static_cast<std::size_t>(count), false) {
    threads_.reserve(ended_.size());
    for (std::size_t i = 0; i < ended_.size(); ++i) threads_.emplace_back([this, i] { Work(i); });
  }
  RequestThreads(const RequestThreads&) = delete;
  RequestThreads& operator=(const RequestThreads&) = delete;
  // Joins every thread: after a Stop() that left some running, the caller ends the process instead
  // of coming here (HttpServer::Run).
  ~RequestThreads() {
    BeginStop();
    for (std::thread& thread : threads_)
      if (thread.joinable()) thread.join();
  }

  void Enqueue(std::function<void()> task) {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      if (stopping_) return;
      tasks_.push_back(std::move(task));
    }
    wake_.notify_one();
  }

  // Drops the tasks not started and waits until `deadline` for those running; joins the threads
  // that ended and returns how many still run.
  std::size_t Stop(Clock::time_point deadline) {
    BeginStop();
    std::unique_lock<std::mutex> lock(mutex_);
    ended_signal_.wait_until(lock, deadline, [this] { return ended_count_ == threads_.size(); });
    std::size_t still_running = 0;
    for (std::size_t i = 0; i < threads_.size(); ++i) {
      if (ended_[i] && threads_[i].joinable()) threads_[i].join();
      if (!ended_[i]) ++still_running;
    }
    return still_running;
  }

 private:
  void BeginStop() {
    std::deque<std::function<void()>> dropped;  // their connections are let go of outside the lock
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      stopping_ = true;
      dropped.swap(tasks_);
    }
    wake_.notify_all();
  }

  void Work(std::size_t index) {
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      wake_.wait(lock, [this] { return stopping_ || !tasks_.empty(); });
      if (stopping_) break;
      std::function<void()> task = std::move(tasks_.front());
      tasks_.pop_front();
      lock.unlock();
      task();
      task = nullptr;  // its connection is let go of before the next wait
      lock.lock();
    }
    ended_[index] = true;
    ++ended_count_;
    ended_signal_.notify_all();
  }

  std::mutex mutex_;
  std::condition_variable wake_;
  std::condition_variable ended_signal_;
  std::deque<std::function<void()>> tasks_;
  std::vector<bool> ended_;  // by thread, under mutex_
  std::size_t ended_count_ = 0;
  std::vector<std::thread> threads_;
  bool stopping_ = false;
};

class HttpConnection;

struct HttpServerState {
  explicit HttpServerState(HttpServerOptions server_options)
      : options(std::move(server_options)), threads(options.threads) {}

  void Accept();
  void OnAccepted(const beast::error_code& error, Tcp::socket socket);
  void BeginStop();
  void CloseAll();
  // A connection's end (on the I/O thread): it is no longer counted.
  void Forget(std::uint64_t id, bool refused);

  // Declared first, destroyed last: the handlers it holds (and their connections) go with it.
  net::io_context io{1};
  Tcp::acceptor acceptor{io};
  net::steady_timer accept_retry{io};
  net::steady_timer stop_timer{io};
  HttpServerOptions options;
  RequestThreads threads;
  // The open connections (I/O thread only): those being answered 503 are `refused` of them.
  std::map<std::uint64_t, std::weak_ptr<HttpConnection>> open;
  std::size_t refused = 0;
  std::uint64_t next_id = 0;
  bool stopping = false;
  bool accept_failing = false;
  Clock::time_point stop_requested{};
};

// One accepted connection, on the I/O thread: reads a request within its deadline, has it
// answered (at once or by a request thread), writes the answer, and reads the next.
class HttpConnection : public std::enable_shared_from_this<HttpConnection> {
 public:
  HttpConnection(HttpServerState& server, Tcp::socket socket, std::uint64_t id, bool refused)
      : server_(server), stream_(std::move(socket)), buffer_(kReadBufferBytes), id_(id), refused_(refused) {
    beast::error_code ignored;
    // An answer leaves as one write; without Nagle's algorithm it never waits for the client's
    // delayed acknowledgement of an earlier one (40 ms on Linux).
    stream_.socket().set_option(Tcp::no_delay(true), ignored);
  }

  void Start() {
    if (refused_) {
      Answer(JsonError(503, "napkin serve has " + std::to_string(kMaxConnections) +
                                " connections open, as many as it takes; retry shortly."),
             false);
      return;
    }
    ReadRequest();
  }

  // Whether it waits for a request (nothing of it is in progress): closed at once on Stop().
  bool idle() const { return phase_ == Phase::kReading || phase_ == Phase::kLingering; }

  void Close() {
    if (phase_ == Phase::kClosed) return;
    phase_ = Phase::kClosed;
    stream_.close();
    server_.Forget(id_, refused_);
  }

 private:
  enum class Phase { kReading, kAnswering, kWriting, kLingering, kClosed };

  void ReadRequest() {
    phase_ = Phase::kReading;
    // What the previous request on the connection said is not this one's (a refusal of this one
    // before its start line is read is HTTP/1.1, with a body).
    request_ = HttpRequest{};
    keep_alive_ = false;
    head_ = false;
    version_ = 11;
    parser_.emplace();
    parser_->header_limit(static_cast<std::uint32_t>(kMaxHeaderBytes));
    parser_->body_limit(kMaxBodyBytes);
    stream_.expires_after(kRequestDeadline);
    http::async_read(
        stream_, buffer_, *parser_,
        [self = shared_from_this()](const beast::error_code& error, std::size_t) { self->OnRead(error); });
  }

  void OnRead(const beast::error_code& error) {
    if (phase_ == Phase::kClosed) return;
    if (error) {
      OnReadFailed(error);
      return;
    }
    const auto& message = parser_->get();
    request_.method = std::string(message.method_string());
    request_.target = std::string(message.target());
    request_.path = DecodedPath(request_.target);
    for (const auto& field : message) request_.fields.emplace_back(field.name_string(), field.value());
    keep_alive_ = message.keep_alive();
    head_ = message.method() == http::verb::head;
    version_ = message.version();
    if (request_.target.size() > kMaxTargetBytes) {
      Refuse(JsonError(414, "the request target is " + std::to_string(request_.target.size()) +
                                " bytes, more than the " + std::to_string(kMaxTargetBytes) +
                                " napkin serve accepts."));
      return;
    }
    if (request_.fields.size() > kMaxHeaderFields) {
      Refuse(JsonError(431, "the request has " + std::to_string(request_.fields.size()) +
                                " header fields, more than the " + std::to_string(kMaxHeaderFields) +
                                " napkin serve accepts."));
      return;
    }
    Routed routed;
    try {
      routed = server_.options.route(request_);
    } catch (...) {
      routed = ErrorResponse(std::current_exception(), "");
    }
    if (Response* response = std::get_if<Response>(&routed)) {
      Answer(std::move(*response), keep_alive_);
      return;
    }
    phase_ = Phase::kAnswering;
    // The answer comes back to the I/O thread, which alone touches the connection.
    server_.threads.Enqueue([self = shared_from_this(), executor = stream_.get_executor(),
                             work = std::move(std::get<RequestWork>(routed))] {
      Response response;
      try {
        response = work();
      } catch (...) {
        response = ErrorResponse(std::current_exception(), "");
      }
      net::post(executor, [self, response = std::move(response)]() mutable {
        if (self->phase_ == Phase::kAnswering) self->Answer(std::move(response), self->keep_alive_);
      });
    });
  }

  void OnReadFailed(const beast::error_code& error) {
    if (error == beast::error::timeout) {
      // The stream closed the socket at the deadline: a request that trickles in gets no thread.
      spdlog::debug("a connection sent no complete request within {} s: closed", kRequestDeadline.count());
      Close();
    } else if (error == http::error::header_limit || error == http::error::buffer_overflow) {
      // The request line alone too long (no line end within the limit) is a 414, as below.
      const std::string_view read(static_cast<const char*>(buffer_.data().data()), buffer_.size());
      const std::size_t line_end = read.find("\r\n");
      if (line_end == std::string_view::npos || line_end > kMaxTargetBytes)
        Refuse(JsonError(414, "the request line is longer than the " + std::to_string(kMaxTargetBytes) +
                                  " bytes napkin serve accepts."));
      else
        Refuse(JsonError(431, "the request's header is larger than the " +
                                  std::to_string(kMaxHeaderBytes / 1024) + " KiB napkin serve accepts."));
    } else if (error == http::error::body_limit) {
      Refuse(JsonError(413, "the request has a body larger than the " + std::to_string(kMaxBodyBytes / 1024) +
                                " KiB napkin serve accepts (its routes take none)."));
    } else if (IsMalformedRequest(error)) {
      Refuse(JsonError(400, "the request is not well-formed HTTP/1.1 (" + error.message() + ")."));
    } else {
      // The client went (end of stream, reset) or Stop() closed the connection.
      Close();
    }
  }

  // A final answer: the connection is closed after it.
  void Refuse(Response response) {
    keep_alive_ = false;
    Answer(std::move(response), false);
  }

  void Answer(Response answer, bool keep_alive) {
    if (server_.stopping) keep_alive = false;
    phase_ = Phase::kWriting;
    response_.emplace();
    response_->version(version_);
    response_->result(static_cast<unsigned>(answer.status));
    response_->set(http::field::content_type, answer.content_type);
    for (const auto& [name, value] : answer.headers) response_->set(name, value);
    response_->keep_alive(keep_alive);
    if (keep_alive) response_->set("Keep-Alive", "timeout=" + std::to_string(kRequestDeadline.count()));
    response_->body() = std::move(answer.body);
    response_->prepare_payload();
    // HEAD: the header of the GET answer (its Content-Length too), no body.
    if (head_) response_->body().clear();
    server_.options.on_answered(request_, answer.status);
    stream_.expires_after(WriteDeadline(response_->body().size()));
    http::async_write(stream_, *response_,
                      [self = shared_from_this(), keep_alive](const beast::error_code& error, std::size_t) {
                        self->OnWritten(error, keep_alive);
                      });
  }

  void OnWritten(const beast::error_code& error, bool keep_alive) {
    if (phase_ == Phase::kClosed) return;
    response_.reset();
    if (error) {
      Close();
    } else if (!keep_alive || server_.stopping) {
      Linger();
    } else {
      ReadRequest();
    }
  }

  void Linger() {
    phase_ = Phase::kLingering;
    beast::error_code ignored;
    stream_.socket().shutdown(Tcp::socket::shutdown_send, ignored);
    stream_.expires_after(kLingerTime);
    Drain();
  }

  void Drain() {
    stream_.async_read_some(net::buffer(drain_),
                            [self = shared_from_this()](const beast::error_code& error, std::size_t) {
                              if (self->phase_ != Phase::kLingering) return;
                              if (error)
                                self->Close();
                              else
                                self->Drain();
                            });
  }

  HttpServerState& server_;
  beast::tcp_stream stream_;
  beast::flat_buffer buffer_;
  std::optional<http::request_parser<http::string_body>> parser_;
  std::optional<http::response<http::string_body>> response_;
  std::array<char, 4096> drain_{};
  HttpRequest request_;
  std::uint64_t id_;
  bool refused_;
  Phase phase_ = Phase::kReading;
  bool keep_alive_ = false;
  bool head_ = false;
  unsigned version_ = 11;
};

}  // namespace detail

void detail::HttpServerState::Accept() {
  acceptor.async_accept(
      [this](const beast::error_code& error, Tcp::socket socket) { OnAccepted(error, std::move(socket)); });
}

void detail::HttpServerState::OnAccepted(const beast::error_code& error, Tcp::socket socket) {
  if (stopping) return;
  if (error) {
    // Out of descriptors (EMFILE) or a connection gone before it was taken: try again shortly.
    if (!accept_failing)
      spdlog::warn("napkin serve cannot accept a connection ({}); retrying", error.message());
    accept_failing = true;
    accept_retry.expires_after(kAcceptRetry);
    accept_retry.async_wait([this](const beast::error_code& wait_error) {
      if (!wait_error && !stopping) Accept();
    });
    return;
  }
  accept_failing = false;
  const bool over_cap = open.size() - refused >= kMaxConnections;
  if (over_cap && refused >= kMaxRefusedConnections) {
    beast::error_code ignored;
    socket.close(ignored);
  } else {
    const std::uint64_t id = next_id++;
    auto connection = std::make_shared<detail::HttpConnection>(*this, std::move(socket), id, over_cap);
    open.emplace(id, connection);
    if (over_cap) ++refused;
    connection->Start();
  }
  Accept();
}

void detail::HttpServerState::Forget(std::uint64_t id, bool was_refused) {
  if (open.erase(id) == 0) return;
  if (was_refused) --refused;
  if (stopping && open.empty()) io.stop();
}

void detail::HttpServerState::BeginStop() {
  if (stopping) return;
  stopping = true;
  stop_requested = Clock::now();
  beast::error_code ignored;
  acceptor.close(ignored);
  accept_retry.cancel();
  // Close() erases from `open`: collect first.
  std::vector<std::shared_ptr<detail::HttpConnection>> idle;
  for (const auto& [id, weak] : open)
    if (const std::shared_ptr<detail::HttpConnection> connection = weak.lock();
        connection && connection->idle())
      idle.push_back(connection);
  for (const std::shared_ptr<detail::HttpConnection>& connection : idle) connection->Close();
  if (open.empty()) {
    io.stop();
    return;
  }
  stop_timer.expires_after(kStopGrace);
  stop_timer.async_wait([this](const beast::error_code&) { CloseAll(); });
}

void detail::HttpServerState::CloseAll() {
  std::vector<std::shared_ptr<detail::HttpConnection>> all;
  for (const auto& [id, weak] : open)
    if (std::shared_ptr<detail::HttpConnection> connection = weak.lock())
      all.push_back(std::move(connection));
  for (const std::shared_ptr<detail::HttpConnection>& connection : all) connection->Close();
  io.stop();
}

HttpServer::HttpServer(HttpServerOptions options)
    : state_(std::make_unique<detail::HttpServerState>(std::move(options))) {
  detail::HttpServerState& state = *state_;
  const std::string named = state.options.host + ":" + std::to_string(state.options.port);
  beast::error_code error;
  Tcp::resolver resolver(state.io);
  const Tcp::resolver::results_type addresses =
      resolver.resolve(state.options.host, std::to_string(state.options.port), Tcp::resolver::passive, error);
  for (const auto& address : addresses) {
    beast::error_code bind_error;
    Tcp::acceptor& acceptor = state.acceptor;
    acceptor.open(address.endpoint().protocol(), bind_error);
    if (!bind_error) acceptor.set_option(net::socket_base::reuse_address(true), bind_error);
    if (!bind_error) acceptor.bind(address.endpoint(), bind_error);
    if (!bind_error) acceptor.listen(net::socket_base::max_listen_connections, bind_error);
    if (!bind_error) break;
    beast::error_code ignored;
    acceptor.close(ignored);
  }
  if (!state.acceptor.is_open())
    throw InputError("napkin serve cannot listen on " + named +
                     " (the address is not this machine's, or the port is in use).");
}

HttpServer::~HttpServer() = default;

int HttpServer::port() const { return state_->acceptor.local_endpoint().port(); }

std::size_t HttpServer::Run() {
  detail::HttpServerState& state = *state_;
  state.Accept();
  state.io.run();
  // Stopped: no connection is left; what the request threads still do is abandoned at kStopThreadsTime.
  return state.threads.Stop(state.stop_requested + kStopThreadsTime);
}

void HttpServer::Stop() {
  net::post(state_->io, [state = state_.get()] { state->BeginStop(); });
}

}  // namespace napkin::serve
