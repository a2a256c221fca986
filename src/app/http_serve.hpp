// A minimal HTTP/1.1 responder for one page: every GET (or HEAD) of / answers with the page, any
// other path 404, any other method 405; one connection at a time, closed after each response. It
// listens on 127.0.0.1 only, so the page is not exposed beyond the machine.
#pragma once
#include <csignal>
#include <functional>
#include <string>

namespace nmdp::app {

class PageServer {
 public:
  // Binds 127.0.0.1:port (0: a free port chosen by the system). InputError when it cannot.
  explicit PageServer(int port);
  ~PageServer();
  PageServer(const PageServer&) = delete;
  PageServer& operator=(const PageServer&) = delete;

  int port() const { return port_; }
  // Answers requests with `page` (text/html) until *stop becomes nonzero.
  void serve(const std::string& page, const volatile std::sig_atomic_t* stop);

 private:
  int socket_ = -1;
  int port_ = 0;
};

}  // namespace nmdp::app
