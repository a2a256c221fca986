#include "app/http_serve.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstring>

#include "common/input_error.hpp"

namespace nmdp::app {

namespace {

// A request's head is short; a client that sends more, or nothing for this long, is answered or dropped.
constexpr size_t kMaxRequestHead = 16 * 1024;
constexpr int kClientTimeoutMs = 5000;
constexpr int kStopPollMs = 100;  // how often the stop flag is looked at while idle

bool sendAll(int fd, const char* data, size_t size) {
  while (size > 0) {
    const ssize_t n = ::send(fd, data, size, MSG_NOSIGNAL);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    data += n;
    size -= static_cast<size_t>(n);
  }
  return true;
}

// The request line and headers, up to the blank line; "" when the client sent nothing usable.
std::string readHead(int fd, const volatile std::sig_atomic_t* stop) {
  std::string head;
  char buffer[4096];
  while (head.find("\r\n\r\n") == std::string::npos && head.find("\n\n") == std::string::npos && head.size() < kMaxRequestHead) {
    pollfd p{fd, POLLIN, 0};
    const int ready = ::poll(&p, 1, kClientTimeoutMs);
    if (ready < 0 && errno == EINTR && !*stop) continue;
    if (ready <= 0 || *stop) return head;
    const ssize_t n = ::recv(fd, buffer, sizeof buffer, 0);
    if (n <= 0) break;
    head.append(buffer, static_cast<size_t>(n));
  }
  return head;
}

void respond(int fd, const std::string& head, const std::string& page) {
  const size_t line_end = head.find_first_of("\r\n");
  const std::string line = head.substr(0, line_end);
  const size_t space = line.find(' ');
  const std::string method = line.substr(0, space);
  std::string target = space == std::string::npos ? "" : line.substr(space + 1);
  target = target.substr(0, target.find(' '));
  target = target.substr(0, target.find('?'));
  std::string status = "200 OK", type = "text/html; charset=utf-8";
  const std::string* body = &page;
  static const std::string kNotFound = "not found\n", kNotAllowed = "only GET and HEAD are served\n";
  if (method != "GET" && method != "HEAD") {
    status = "405 Method Not Allowed";
    body = &kNotAllowed;
    type = "text/plain";
  } else if (target != "/" && target != "/index.html") {
    status = "404 Not Found";
    body = &kNotFound;
    type = "text/plain";
  }
  const std::string reply = "HTTP/1.1 " + status + "\r\nContent-Type: " + type + "\r\nContent-Length: " +
                            std::to_string(body->size()) + "\r\nCache-Control: no-store\r\nConnection: close\r\n" +
                            (status.rfind("405", 0) == 0 ? "Allow: GET, HEAD\r\n" : "") + "\r\n";
  if (sendAll(fd, reply.data(), reply.size()) && method != "HEAD") sendAll(fd, body->data(), body->size());
}

}  // namespace

PageServer::PageServer(int port) {
  if (port < 0 || port > 65535) throw InputError("--serve: the port must be between 0 and 65535, got " + std::to_string(port));
  socket_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (socket_ < 0) throw InputError(std::string("--serve: cannot open a socket: ") + std::strerror(errno));
  const int yes = 1;
  ::setsockopt(socket_, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  address.sin_port = htons(static_cast<std::uint16_t>(port));
  if (::bind(socket_, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0 || ::listen(socket_, 16) != 0) {
    const std::string why = std::strerror(errno);
    ::close(socket_);
    throw InputError("--serve " + std::to_string(port) + ": cannot listen on 127.0.0.1:" + std::to_string(port) + ": " + why);
  }
  socklen_t size = sizeof address;
  ::getsockname(socket_, reinterpret_cast<sockaddr*>(&address), &size);
  port_ = ntohs(address.sin_port);
}

PageServer::~PageServer() {
  if (socket_ >= 0) ::close(socket_);
}

void PageServer::serve(const std::string& page, const volatile std::sig_atomic_t* stop) {
  while (!*stop) {
    pollfd p{socket_, POLLIN, 0};
    if (::poll(&p, 1, kStopPollMs) <= 0) continue;  // a timeout, or EINTR from the signal itself
    const int client = ::accept4(socket_, nullptr, nullptr, SOCK_CLOEXEC);
    if (client < 0) continue;
    const std::string head = readHead(client, stop);
    if (!head.empty() && !*stop) respond(client, head, page);
    ::shutdown(client, SHUT_WR);
    ::close(client);
  }
}

}  // namespace nmdp::app
