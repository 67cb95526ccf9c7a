#include "base/child_process.h"

#include <poll.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <ostream>

extern char** environ;

namespace pcbench {

namespace {

// Both ends of a pipe, closed on every path out.
struct Pipe {
  int ends[2] = {-1, -1};
  Pipe() {
    if (pipe(ends) != 0) ends[0] = ends[1] = -1;
  }
  ~Pipe() {
    for (int& fd : ends) close_end(fd);
  }
  Pipe(const Pipe&) = delete;
  Pipe& operator=(const Pipe&) = delete;
  bool ok() const { return ends[0] >= 0; }
  static void close_end(int& fd) {
    if (fd >= 0) close(fd);
    fd = -1;
  }
};

// Copies what the child writes on both pipes to the streams until both are closed (reading
// both at once: a child that fills one pipe while we wait on the other would never finish).
void forward(Pipe& out_pipe, Pipe& err_pipe, std::ostream& out, std::ostream& err) {
  std::array<pollfd, 2> fds = {pollfd{out_pipe.ends[0], POLLIN, 0},
                               pollfd{err_pipe.ends[0], POLLIN, 0}};
  std::array<std::ostream*, 2> streams = {&out, &err};
  std::array<char, 4096> buffer{};
  int open = 2;
  while (open > 0) {
    if (poll(fds.data(), fds.size(), -1) < 0) {
      if (errno == EINTR) continue;
      break;
    }
    for (std::size_t i = 0; i < fds.size(); ++i) {
      if (fds[i].fd < 0 || fds[i].revents == 0) continue;
      const ssize_t n = read(fds[i].fd, buffer.data(), buffer.size());
      if (n > 0) {
        streams[i]->write(buffer.data(), n);
        streams[i]->flush();
      } else if (n == 0 || errno != EINTR) {
        fds[i].fd = -1;  // poll ignores negative descriptors
        --open;
      }
    }
  }
}

}  // namespace

int run_child_process(const std::vector<std::string>& argv, std::ostream& out, std::ostream& err) {
  Pipe out_pipe, err_pipe;
  if (!out_pipe.ok() || !err_pipe.ok()) {
    err << "pcbench: error: cannot create a pipe: " << std::strerror(errno) << "\n";
    return -1;
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, out_pipe.ends[1], STDOUT_FILENO);
  posix_spawn_file_actions_adddup2(&actions, err_pipe.ends[1], STDERR_FILENO);
  posix_spawn_file_actions_addclose(&actions, out_pipe.ends[0]);
  posix_spawn_file_actions_addclose(&actions, err_pipe.ends[0]);
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, argv[0].c_str(), &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  // Our copies of the write ends must go, or the reads below never see the end of the output.
  Pipe::close_end(out_pipe.ends[1]);
  Pipe::close_end(err_pipe.ends[1]);
  if (spawned != 0) {
    err << "pcbench: error: cannot run " << argv[0] << ": " << std::strerror(spawned) << "\n";
    return -1;
  }
  forward(out_pipe, err_pipe, out, err);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return -1;
}

}  // namespace pcbench
