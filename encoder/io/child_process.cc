#include "encoder/io/child_process.h"

#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>

extern char** environ;

namespace fvv {
namespace {

// Children alive now, for the signal handler: slots hold pids, 0 when free.
constexpr int kMaxTrackedChildren = 256;
std::atomic<pid_t> g_children[kMaxTrackedChildren];

void Track(pid_t pid) {
  for (std::atomic<pid_t>& slot : g_children) {
    pid_t free_slot = 0;
    if (slot.compare_exchange_strong(free_slot, pid)) return;
  }
}

void Untrack(pid_t pid) {
  for (std::atomic<pid_t>& slot : g_children) {
    pid_t mine = pid;
    if (slot.compare_exchange_strong(mine, 0)) return;
  }
}

extern "C" void KillChildrenAndDie(int sig) {
  for (std::atomic<pid_t>& slot : g_children) {
    const pid_t pid = slot.load();
    if (pid > 0) kill(pid, SIGKILL);
  }
  signal(sig, SIG_DFL);
  raise(sig);
}

}  // namespace

void KillChildrenOnTerminatingSignals() {
  for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGQUIT}) {
    struct sigaction action {};
    action.sa_handler = KillChildrenAndDie;
    sigemptyset(&action.sa_mask);
    sigaction(sig, &action, nullptr);
  }
}

StatusOr<std::unique_ptr<ChildProcess>> ChildProcess::Start(std::vector<std::string> args,
                                                            Pipe pipe) {
  if (args.empty()) return InvalidArgument("no program to start");
  int pipe_fd[2];
  // Close-on-exec on both ends: the child gets its end through dup2 (which
  // clears the flag on the copy), every other child gets neither.
  if (pipe2(pipe_fd, O_CLOEXEC) != 0) {
    return IoError("pipe failed: " + std::string(std::strerror(errno)));
  }
  const bool reading = pipe == Pipe::kReadStdout;
  const int ours = reading ? pipe_fd[0] : pipe_fd[1];
  const int theirs = reading ? pipe_fd[1] : pipe_fd[0];
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, theirs, reading ? STDOUT_FILENO : STDIN_FILENO);
  if (reading) posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  // The child starts with default signal handling and an empty mask, whatever
  // this process has set for itself.
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  sigset_t none, all;
  sigemptyset(&none);
  sigfillset(&all);
  posix_spawnattr_setsigmask(&attr, &none);
  posix_spawnattr_setsigdefault(&attr, &all);
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = -1;
  const int rc = posix_spawnp(&pid, args[0].c_str(), &actions, &attr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attr);
  close(theirs);
  if (rc != 0) {
    close(ours);
    return IoError("cannot start " + args[0] + " (" + std::strerror(rc) + ")");
  }
  Track(pid);
  std::unique_ptr<ChildProcess> child(new ChildProcess());
  child->name_ = args[0];
  child->fd_ = ours;
  child->pid_ = pid;
  return child;
}

ChildProcess::~ChildProcess() { Kill(); }

void ChildProcess::ClosePipe() {
  if (fd_ >= 0) close(fd_);
  fd_ = -1;
}

ssize_t ChildProcess::Read(void* data, size_t size) {
  for (;;) {
    const ssize_t n = read(fd_, data, size);
    if (n < 0 && errno == EINTR) continue;
    return n;
  }
}

bool ChildProcess::Write(const void* data, size_t size) {
  // A child that stopped reading raises SIGPIPE, whose default ends the whole
  // process: block it in this thread while writing, and discard the one the
  // write raised, so the caller gets false instead.
  sigset_t pipe_signal, old_mask;
  sigemptyset(&pipe_signal);
  sigaddset(&pipe_signal, SIGPIPE);
  pthread_sigmask(SIG_BLOCK, &pipe_signal, &old_mask);
  const char* p = static_cast<const char*>(data);
  bool ok = true;
  while (size > 0) {
    const ssize_t n = write(fd_, p, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      if (errno == EPIPE) {
        const timespec no_wait{0, 0};
        sigtimedwait(&pipe_signal, nullptr, &no_wait);
      }
      ok = false;
      break;
    }
    p += n;
    size -= static_cast<size_t>(n);
  }
  pthread_sigmask(SIG_SETMASK, &old_mask, nullptr);
  return ok;
}

int ChildProcess::Finish() {
  ClosePipe();
  if (pid_ <= 0) return -1;
  int status = 0;
  while (waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
  }
  Untrack(pid_);
  pid_ = -1;
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return -1;
}

void ChildProcess::Kill() {
  // Killed before its pipe closes, so it dies without reporting a broken pipe.
  if (pid_ > 0) kill(pid_, SIGKILL);
  ClosePipe();
  if (pid_ <= 0) return;
  int status = 0;
  while (waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
  }
  Untrack(pid_);
  pid_ = -1;
}

StatusOr<std::string> RunForOutput(std::vector<std::string> args, int* exit_code) {
  StatusOr<std::unique_ptr<ChildProcess>> child =
      ChildProcess::Start(std::move(args), ChildProcess::Pipe::kReadStdout);
  if (!child.ok()) return child.status();
  std::string out;
  char buffer[4096];
  for (;;) {
    const ssize_t n = (*child)->Read(buffer, sizeof(buffer));
    if (n <= 0) break;
    if (out.size() < (1u << 20)) out.append(buffer, static_cast<size_t>(n));
  }
  *exit_code = (*child)->Finish();
  return out;
}

bool HaveProgram(const std::string& name) {
  const char* path = std::getenv("PATH");
  if (!path) return false;
  const std::string dirs(path);
  size_t start = 0;
  while (start <= dirs.size()) {
    const size_t end = dirs.find(':', start);
    const std::string dir =
        dirs.substr(start, end == std::string::npos ? std::string::npos : end - start);
    if (!dir.empty() && access((dir + "/" + name).c_str(), X_OK) == 0) return true;
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return false;
}

}  // namespace fvv
