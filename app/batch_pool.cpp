#include "batch_pool.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <map>
#include <new>
#include <stdexcept>

#include "meshcore/error.h"

namespace gm {

namespace {

using Clock = std::chrono::steady_clock;

struct Child {
    int index = 0;
    std::FILE* result = nullptr;  // what the child's work returned
    std::FILE* err = nullptr;     // the child's stderr
    Clock::time_point start;
};

void writeAll(int fd, const std::string& s) {
    size_t done = 0;
    while (done < s.size()) {
        const ssize_t n = ::write(fd, s.data() + done, s.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return;
        done += static_cast<size_t>(n);
    }
}

std::string readAll(std::FILE* f) {
    std::string s;
    std::rewind(f);
    char buf[4096];
    size_t n;
    while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) s.append(buf, n);
    std::fclose(f);
    return s;
}

// In the child: the work, its outcome written to `resultFd` ("ok\n" or "error\n", then the text).
[[noreturn]] void runChild(int index, const std::function<std::string(int)>& work, pid_t parent,
                           int resultFd, int errFd) {
    ::prctl(PR_SET_PDEATHSIG, SIGTERM);
    if (::getppid() != parent) ::_exit(3);  // the parent died before prctl
    sigset_t none;
    sigemptyset(&none);
    ::sigprocmask(SIG_SETMASK, &none, nullptr);
    ::dup2(errFd, 2);
    ::dup2(errFd, 1);
    const int null = ::open("/dev/null", O_RDONLY);
    if (null >= 0) ::dup2(null, 0);
    std::string outcome;
    try {
        outcome = "ok\n" + work(index);
    } catch (const std::bad_alloc&) {
        outcome = "error\nout of memory";
    } catch (const std::exception& e) {
        outcome = std::string("error\n") + e.what();
    } catch (...) {
        outcome = "error\nunknown failure";
    }
    std::fflush(stdout);
    std::fflush(stderr);
    writeAll(resultFd, outcome);
    ::_exit(0);
}

ChildOutcome outcomeOf(Child& c, int status, const rusage& usage) {
    ChildOutcome o;
    o.seconds = std::chrono::duration<double>(Clock::now() - c.start).count();
    o.cpuSeconds = usage.ru_utime.tv_sec + usage.ru_utime.tv_usec * 1e-6 + usage.ru_stime.tv_sec +
                   usage.ru_stime.tv_usec * 1e-6;
    o.peakRssMb = usage.ru_maxrss / 1024.0;
    o.messages = readAll(c.err);
    const std::string result = readAll(c.result);
    if (WIFSIGNALED(status)) {
        const int sig = WTERMSIG(status);
        o.text = std::string("the conversion was killed by signal ") + std::to_string(sig) + " (" +
                 strsignal(sig) + ")" + (sig == SIGKILL ? "; out of memory?" : "");
    } else if (result.compare(0, 3, "ok\n") == 0) {
        o.ok = WEXITSTATUS(status) == 0;
        o.text = result.substr(3);
    } else if (result.compare(0, 6, "error\n") == 0) {
        o.text = result.substr(6);
    } else {
        o.text = "the conversion ended with exit status " + std::to_string(WEXITSTATUS(status));
    }
    return o;
}

}  // namespace

void runInChildProcesses(const std::vector<int>& order, int workers,
                         const std::function<std::string(int)>& work,
                         const std::function<void(int, const ChildOutcome&)>& done,
                         const std::function<void()>& tick) {
    sigset_t childSignal, previous;
    sigemptyset(&childSignal);
    sigaddset(&childSignal, SIGCHLD);
    ::sigprocmask(SIG_BLOCK, &childSignal, &previous);
    const pid_t self = ::getpid();
    std::map<pid_t, Child> running;
    size_t next = 0;
    while (next < order.size() || !running.empty()) {
        while (static_cast<int>(running.size()) < workers && next < order.size()) {
            Child c;
            c.index = order[next++];
            c.result = std::tmpfile();
            c.err = std::tmpfile();
            if (!c.result || !c.err) throw Error("cannot create a temporary file", "tmpfile");
            std::fflush(stdout);
            std::fflush(stderr);
            c.start = Clock::now();
            const pid_t pid = ::fork();
            if (pid < 0) throw Error(std::string("cannot start a process: ") + std::strerror(errno), "fork");
            if (pid == 0) runChild(c.index, work, self, fileno(c.result), fileno(c.err));
            running[pid] = c;
        }
        int status = 0;
        rusage usage{};
        const pid_t pid = ::wait4(-1, &status, WNOHANG, &usage);
        if (pid > 0 && running.count(pid)) {
            Child c = running[pid];
            running.erase(pid);
            done(c.index, outcomeOf(c, status, usage));
            continue;
        }
        const timespec halfSecond{0, 500000000};
        ::sigtimedwait(&childSignal, nullptr, &halfSecond);
        tick();
    }
    ::sigprocmask(SIG_SETMASK, &previous, nullptr);
}

}  // namespace gm
