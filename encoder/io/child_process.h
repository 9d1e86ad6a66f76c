// A child program (ffmpeg, ffprobe) joined to this process by one pipe: we
// read its standard output, or we write its standard input. The pipe is
// close-on-exec, so no other child inherits it: a child whose reader goes away
// sees a broken pipe and stops, and one whose writer closes sees the end of its
// input, whatever else runs beside it. The destructor never waits on a child
// that is still busy: it kills it first, then reaps it.
#ifndef FVV_ENCODER_IO_CHILD_PROCESS_H_
#define FVV_ENCODER_IO_CHILD_PROCESS_H_

#include <sys/types.h>

#include <memory>
#include <string>
#include <vector>

#include "codec/base/status.h"

namespace fvv {

class ChildProcess {
 public:
  enum class Pipe {
    kReadStdout,  // fd() reads the child's standard output; its stdin is /dev/null
    kWriteStdin,  // fd() writes the child's standard input; its stdout is ours
  };

  // Starts `args[0]` (looked up on PATH) with `args`.
  static StatusOr<std::unique_ptr<ChildProcess>> Start(std::vector<std::string> args, Pipe pipe);
  ~ChildProcess();
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  int fd() const { return fd_; }
  pid_t pid() const { return pid_; }

  // Reads up to `size` bytes, retrying on interruption; 0 at the end of output.
  ssize_t Read(void* data, size_t size);
  // Writes all `size` bytes; false when the child stopped reading.
  bool Write(const void* data, size_t size);

  // Closes our end of the pipe and waits for the child to exit by itself:
  // its exit code, or 128 + the signal that ended it.
  int Finish();
  // Ends the child now (SIGKILL) and reaps it. Safe to call more than once.
  void Kill();

 private:
  ChildProcess() = default;
  void ClosePipe();
  std::string name_;
  int fd_ = -1;
  pid_t pid_ = -1;
};

// The whole standard output of a short-lived command (at most 1 MiB kept) and
// its exit code.
StatusOr<std::string> RunForOutput(std::vector<std::string> args, int* exit_code);

// For programs (not libraries, whose host owns its signals): SIGINT, SIGTERM,
// SIGHUP and SIGQUIT kill every child started through ChildProcess that is
// still running, then end this process as the signal would have.
void KillChildrenOnTerminatingSignals();

// Whether an executable called `name` is on PATH.
bool HaveProgram(const std::string& name);

}  // namespace fvv

#endif  // FVV_ENCODER_IO_CHILD_PROCESS_H_
