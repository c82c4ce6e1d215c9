/* POSIX services the Fortran standard lacks: what kind of file a path names, atomic rename,
 * durable writes (fsync), advisory locks that die with their process, and the signals a batch
 * scheduler sends. Each returns 0 or an errno value; nothing here prints or exits. */
#define _XOPEN_SOURCE 700
#include <errno.h>
#include <pthread.h>
#include <stdlib.h>
#include <fcntl.h>
#include <limits.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <time.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <unistd.h>

/* File kinds of ffrf_file_kind, mirrored in ffrf_core_posix. */
enum { KIND_MISSING = 0, KIND_REGULAR = 1, KIND_DIRECTORY = 2, KIND_FIFO = 3, KIND_DEVICE = 4,
       KIND_OTHER = 5 };

/* Kind and size in bytes of the file `path` names (links followed); errno of stat() when it
 * cannot be inspected for another reason than its absence. */
int ffrf_file_kind(const char *path, int *kind, long long *size)
{
    struct stat st;
    *kind = KIND_MISSING;
    *size = 0;
    if (stat(path, &st) != 0) return errno == ENOENT || errno == ENOTDIR ? 0 : errno;
    *size = (long long)st.st_size;
    if (S_ISREG(st.st_mode)) *kind = KIND_REGULAR;
    else if (S_ISDIR(st.st_mode)) *kind = KIND_DIRECTORY;
    else if (S_ISFIFO(st.st_mode)) *kind = KIND_FIFO;
    else if (S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode)) *kind = KIND_DEVICE;
    else *kind = KIND_OTHER;
    return 0;
}

/* Bytes an unprivileged process may still write in the file system of `path` (statvfs:
 * f_bavail blocks of f_frsize bytes); errno of statvfs() when it cannot be inspected. */
int ffrf_free_space(const char *path, long long *bytes)
{
    struct statvfs st;
    *bytes = 0;
    if (statvfs(path, &st) != 0) return errno;
    *bytes = (long long)st.f_bavail * (long long)st.f_frsize;
    return 0;
}

/* rename(2): replaces `to` atomically within one file system. */
int ffrf_rename(const char *from, const char *to)
{
    return rename(from, to) == 0 ? 0 : errno;
}

/* unlink(2); a missing file is not an error. */
int ffrf_unlink(const char *path)
{
    return unlink(path) == 0 || errno == ENOENT ? 0 : errno;
}

/* Flush a closed file's data to the device (open, fsync, close): a full disk or an I/O error
 * that the page cache hid until now is reported here. */
int ffrf_fsync_path(const char *path)
{
    int fd = open(path, O_RDONLY), status = 0;
    if (fd < 0) return errno;
    if (fsync(fd) != 0 && errno != EINVAL && errno != EROFS) status = errno;
    if (close(fd) != 0 && status == 0) status = errno;
    return status;
}

/* An exclusive advisory lock (flock) on `path`, created if missing. *fd is the descriptor that
 * holds it (-1 when not taken); the kernel releases it when the process ends, even by kill -9.
 * EWOULDBLOCK: another process holds it. */
int ffrf_lock_file(const char *path, int *fd)
{
    *fd = open(path, O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0644);
    /* a symbolic link at the lock's name is no ffrf lock: removed, never followed */
    if (*fd < 0 && errno == ELOOP && unlink(path) == 0)
        *fd = open(path, O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC | O_NOFOLLOW, 0644);
    if (*fd < 0) return errno;
    if (flock(*fd, LOCK_EX | LOCK_NB) != 0) {
        int status = errno == EWOULDBLOCK ? EWOULDBLOCK : errno;
        close(*fd);
        *fd = -1;
        return status;
    }
    return 0;
}

/* Release a lock of ffrf_lock_file and remove its file (the remover holds the lock, so a
 * second run waiting on it never sees a half-removed lock as its own). */
int ffrf_unlock_file(const char *path, int fd)
{
    int status = 0;
    if (fd < 0) return 0;
    if (unlink(path) != 0 && errno != ENOENT) status = errno;
    flock(fd, LOCK_UN);
    close(fd);
    return status;
}

/* The system's words for an errno value. */
void ffrf_errno_text(int code, char *buffer, int length)
{
    if (length <= 0) return;
    snprintf(buffer, (size_t)length, "%s", strerror(code));
}

/* Signals a batch scheduler or a user sends to end a run: SIGTERM (scancel, the time limit),
 * SIGINT (Ctrl-C), SIGHUP (a closed terminal), SIGUSR1 and SIGXCPU (ahead of a time limit).
 * The handler only records the first one; the run checks it between steps (and a modal run
 * between bodies and between the solves of an eigen loop). A second SIGINT (Ctrl-C pressed
 * again) ends the run at once. */
static volatile sig_atomic_t pending_signal = 0;

static void record_signal(int signal_number)
{
    if (pending_signal == 0) {
        pending_signal = signal_number;
        return;
    }
    /* A second Ctrl-C while the first waits for the end of a step (or of a body's modes): the
     * user insists, so end the run at once, as without the handlers. Scheduler signals never
     * escalate: a repeated SIGTERM must not cut the clean end of the run short. */
    if (signal_number == SIGINT && pending_signal == SIGINT) {
        signal(SIGINT, SIG_DFL);
        raise(SIGINT);
    }
}

/* The signals of ffrf_signals_install. */
static const int run_signals[] = {SIGTERM, SIGINT, SIGHUP, SIGUSR1, SIGXCPU};
#define NUM_RUN_SIGNALS (sizeof run_signals / sizeof run_signals[0])

static void run_signal_set(sigset_t *set)
{
    sigemptyset(set);
    for (size_t k = 0; k < NUM_RUN_SIGNALS; ++k) sigaddset(set, run_signals[k]);
}

/* OpenBLAS (pthreads build) starts its worker threads when it is loaded, with every signal
 * unblocked; a signal the main thread blocks (ffrf_signals_hold) would then run in one of them,
 * and with METIS's handler installed there it would longjmp into another thread's stack. So
 * the workers are restarted with the run signals blocked: only the threads of the host (the
 * driver's main thread) take them. Weak references: another BLAS is left alone. */
void blas_thread_shutdown_(void) __attribute__((weak));
int blas_thread_init(void) __attribute__((weak));

/* Record the run signals (sigaction, SA_RESTART: an interrupted read or write goes on; the run
 * stops at its next check of ffrf_signal_pending). */
int ffrf_signals_install(void)
{
    struct sigaction action;
    sigset_t set, previous;
    memset(&action, 0, sizeof action);
    action.sa_handler = record_signal;
    action.sa_flags = SA_RESTART;
    sigemptyset(&action.sa_mask);
    for (size_t k = 0; k < NUM_RUN_SIGNALS; ++k)
        if (sigaction(run_signals[k], &action, NULL) != 0) return errno;
    if (blas_thread_shutdown_ && blas_thread_init) {
        run_signal_set(&set);
        if (pthread_sigmask(SIG_BLOCK, &set, &previous) == 0) {
            blas_thread_shutdown_();
            blas_thread_init();
            pthread_sigmask(SIG_SETMASK, &previous, NULL);
        }
    }
    return 0;
}

/* ---- issue 23, item 1: signal handlers no library can undo ----
 * METIS 5.1's METIS_NodeND installs its own handlers for SIGTERM and SIGABRT (GKlib's
 * gk_sigtrap, to longjmp out of its errors) and puts the previous ones back with SysV
 * signal(): the handler then fires once and SA_RESTART is lost, so a second SIGTERM killed the
 * run. Around such a call the run signals are blocked in the calling thread (a signal that
 * arrives meanwhile stays pending) and every handler is saved; afterwards the saved handlers
 * are put back with sigaction, whatever the library left, and the mask is restored, which
 * delivers a pending signal to ffrf's handler. Calls nest. */
static pthread_mutex_t hold_lock = PTHREAD_MUTEX_INITIALIZER;
static int hold_count = 0;                 /* holds open in the process */
static struct sigaction held_actions[NUM_RUN_SIGNALS + 1];
static _Thread_local int thread_depth = 0; /* holds open in this thread */
static _Thread_local sigset_t held_mask;
static _Thread_local int held_blocked = 0;

/* The handlers are saved by the first hold of the process and put back by its last release
 * (threads of a host may hold at once: a METIS ordering in one, a MUMPS call in another; a
 * save taken while METIS's handler is in place would otherwise put it back for good). The
 * mask is per thread. block = 0: the handlers are saved and put back, the signals stay
 * deliverable (a library known to install no handlers whose calls may last long: a second
 * Ctrl-C must still end the run at once). */
int ffrf_signals_hold(int block)
{
    int status = 0;
    if (thread_depth++ == 0 && block) {
        sigset_t set;
        run_signal_set(&set);
        held_blocked = pthread_sigmask(SIG_BLOCK, &set, &held_mask) == 0;
        if (!held_blocked) status = errno;
    }
    pthread_mutex_lock(&hold_lock);
    if (hold_count++ == 0) {
        for (size_t k = 0; k < NUM_RUN_SIGNALS; ++k)
            if (sigaction(run_signals[k], NULL, &held_actions[k]) != 0 && status == 0)
                status = errno;
        if (sigaction(SIGABRT, NULL, &held_actions[NUM_RUN_SIGNALS]) != 0 && status == 0)
            status = errno;
    }
    pthread_mutex_unlock(&hold_lock);
    return status;
}

int ffrf_signals_release(void)
{
    int status = 0;
    if (thread_depth == 0) return 0;
    pthread_mutex_lock(&hold_lock);
    if (--hold_count == 0) {
        for (size_t k = 0; k < NUM_RUN_SIGNALS; ++k)
            if (sigaction(run_signals[k], &held_actions[k], NULL) != 0 && status == 0)
                status = errno;
        if (sigaction(SIGABRT, &held_actions[NUM_RUN_SIGNALS], NULL) != 0 && status == 0)
            status = errno;
    }
    pthread_mutex_unlock(&hold_lock);
    /* unblocked after the handlers are back: a signal held meanwhile goes to them */
    if (--thread_depth == 0 && held_blocked) {
        held_blocked = 0;
        if (pthread_sigmask(SIG_SETMASK, &held_mask, NULL) != 0 && status == 0) status = errno;
    }
    return status;
}

/* Test points (ctest regression_signal_stages): with FFRF_TEST_SIGNALS="STAGE:N:NAME" in the
 * environment (NAME one of TERM, INT, HUP, USR1, XCPU), the first time the run passes the test
 * point STAGE it sends itself N signals NAME with kill(), as a scheduler would, before it goes
 * on: the stage hit is exact, not timed. "STAGE:N:NAME:async" sends them from a thread of their
 * own, 2 ms apart, while the run goes on into the library call that follows the point (a
 * MUMPS factorisation: signals that arrive while it runs). Without the variable a test point
 * does nothing. */
struct test_signals { int count, number; };

static void *send_test_signals(void *argument)
{
    const struct test_signals *what = argument;
    const struct timespec pause = {0, 2000000};
    for (int k = 0; k < what->count; ++k) {
        nanosleep(&pause, NULL);
        kill(getpid(), what->number);
    }
    return NULL;
}

void ffrf_signal_test_point(const char *stage)
{
    static int fired = 0;
    static struct test_signals what;
    const char *spec = getenv("FFRF_TEST_SIGNALS");
    const char *colon, *name;
    pthread_t thread;
    if (spec == NULL || fired) return;
    if (strncmp(spec, stage, strlen(stage)) != 0 || spec[strlen(stage)] != ':') return;
    colon = spec + strlen(stage);
    what.count = atoi(colon + 1);
    name = strchr(colon + 1, ':');
    name = name ? name + 1 : "TERM";
    what.number = strncmp(name, "INT", 3) == 0 ? SIGINT : strncmp(name, "HUP", 3) == 0 ? SIGHUP
        : strncmp(name, "USR1", 4) == 0 ? SIGUSR1 : strncmp(name, "XCPU", 4) == 0 ? SIGXCPU
        : SIGTERM;
    fired = 1;
    if (strstr(name, ":async") != NULL) {
        /* the thread must not take the signals itself: it inherits a mask that blocks them */
        sigset_t set, previous;
        run_signal_set(&set);
        pthread_sigmask(SIG_BLOCK, &set, &previous);
        if (pthread_create(&thread, NULL, send_test_signals, &what) == 0) pthread_detach(thread);
        pthread_sigmask(SIG_SETMASK, &previous, NULL);
        return;
    }
    for (int k = 0; k < what.count; ++k) kill(getpid(), what.number);
}

/* The first signal recorded since the handlers were installed (0: none). */
int ffrf_signal_pending(void)
{
    return (int)pending_signal;
}

/* Forget a recorded signal (tests). */
void ffrf_signal_clear(void)
{
    pending_signal = 0;
}

/* "SIGTERM" for SIGTERM, "signal N" otherwise. */
void ffrf_signal_name(int signal_number, char *buffer, int length)
{
    const char *name = signal_number == SIGTERM ? "SIGTERM" : signal_number == SIGINT ? "SIGINT"
        : signal_number == SIGHUP ? "SIGHUP" : signal_number == SIGUSR1 ? "SIGUSR1"
        : signal_number == SIGXCPU ? "SIGXCPU" : NULL;
    if (length <= 0) return;
    if (name) snprintf(buffer, (size_t)length, "%s", name);
    else snprintf(buffer, (size_t)length, "signal %d", signal_number);
}

/* ---- results files (issue 10, part 1): output locks, durable copies, full-disk signals ---- */

/* The lock of ffrf_lock_file, made safe against the removal of the lock file by the run that
 * held it: after taking the lock, the path must still name the locked file (same device and
 * inode), else another run removed it in between and the lock is taken again on the new file.
 * EWOULDBLOCK: another process holds it. */
int ffrf_lock_output(const char *path, int *fd)
{
    for (int attempt = 0; attempt < 100; ++attempt) {
        struct stat held, named;
        int status = ffrf_lock_file(path, fd);
        if (status != 0) return status;
        if (fstat(*fd, &held) == 0 && stat(path, &named) == 0 && held.st_dev == named.st_dev
            && held.st_ino == named.st_ino)
            return 0;
        flock(*fd, LOCK_UN);
        close(*fd);
        *fd = -1;
    }
    return EWOULDBLOCK;
}

/* A process limited by RLIMIT_FSIZE (ulimit -f) is killed by SIGXFSZ when a write passes the
 * limit; ignored, the write fails with EFBIG and the run reports it like a full disk. */
int ffrf_ignore_file_size_signal(void)
{
    struct sigaction action;
    memset(&action, 0, sizeof action);
    action.sa_handler = SIG_IGN;
    sigemptyset(&action.sa_mask);
    return sigaction(SIGXFSZ, &action, NULL) == 0 ? 0 : errno;
}

/* Copy the file `from` to `to` (created or truncated, mode 0644) and fsync `to`: the bytes are
 * on the device when this returns 0. Errno of the first failure otherwise (`to` is then
 * incomplete: the caller removes it). */
int ffrf_copy_file(const char *from, const char *to)
{
    char buffer[1 << 16];
    int in = open(from, O_RDONLY | O_CLOEXEC), out, status = 0;
    if (in < 0) return errno;
    /* a new file, never written through a link left at its name (issue 23, item 2) */
    if (unlink(to) != 0 && errno != ENOENT) {
        status = errno;
        close(in);
        return status;
    }
    out = open(to, O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (out < 0) {
        status = errno;
        close(in);
        return status;
    }
    for (;;) {
        ssize_t got = read(in, buffer, sizeof buffer), done = 0;
        if (got < 0) {
            if (errno == EINTR) continue;
            status = errno;
            break;
        }
        if (got == 0) break;
        while (done < got) {
            ssize_t put = write(out, buffer + done, (size_t)(got - done));
            if (put < 0) {
                if (errno == EINTR) continue;
                status = errno;
                break;
            }
            done += put;
        }
        if (status != 0) break;
    }
    if (status == 0 && fsync(out) != 0 && errno != EINVAL && errno != EROFS) status = errno;
    if (close(out) != 0 && status == 0) status = errno;
    close(in);
    return status;
}

/* fsync the folder that holds `path`, so that a rename into it survives a power cut. Errors of
 * file systems that cannot sync a folder are ignored. */
int ffrf_fsync_folder_of(const char *path)
{
    char folder[4096];
    const char *slash = strrchr(path, '/');
    int fd, status = 0;
    if (slash == NULL) snprintf(folder, sizeof folder, ".");
    else if (slash == path) snprintf(folder, sizeof folder, "/");
    else snprintf(folder, sizeof folder, "%.*s", (int)(slash - path), path);
    fd = open(folder, O_RDONLY | O_CLOEXEC);
    if (fd < 0) return 0;
    if (fsync(fd) != 0 && errno != EINVAL && errno != EROFS && errno != EBADF) status = errno;
    close(fd);
    return status;
}

/* Make the signals of ffrf_signals_install restart interrupted system calls (SA_RESTART): a
 * signal that arrives while a mesh or case file is read must not fail that read with EINTR;
 * the run ends at its next check of ffrf_signal_pending instead. */
int ffrf_signals_restart_calls(void)
{
    const int signals[] = {SIGTERM, SIGINT, SIGHUP, SIGUSR1, SIGXCPU};
    for (size_t k = 0; k < sizeof signals / sizeof signals[0]; ++k) {
        struct sigaction action;
        if (sigaction(signals[k], NULL, &action) != 0) return errno;
        action.sa_flags |= SA_RESTART;
        if (sigaction(signals[k], &action, NULL) != 0) return errno;
    }
    return 0;
}

/* ---- issue 23, item 2: outputs never written through a link, never over an input ---- */

/* Create `path` as a new empty regular file: whatever the name holds (a stale temporary file,
 * a symbolic link) is removed first (the link itself, never its target), then the file is
 * created with O_CREAT | O_EXCL | O_NOFOLLOW, which fails rather than follow a link that
 * reappears in between. */
int ffrf_create_new_file(const char *path)
{
    int fd;
    if (unlink(path) != 0 && errno != ENOENT) return errno;
    fd = open(path, O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (fd < 0) return errno;
    return close(fd) == 0 ? 0 : errno;
}

/* The name of the folder entry `path`: the folder resolved by realpath, then "/" and the last
 * component, a link there not followed (what unlink and rename act on); `path` up to
 * 2 PATH_MAX + 1 bytes (resolved_name's). */
static void entry_name(const char *path, char *out, size_t size)
{
    char folder[2 * PATH_MAX + 2], real[PATH_MAX];
    const char *slash = strrchr(path, '/'), *base = slash ? slash + 1 : path;
    if (slash == NULL) snprintf(folder, sizeof folder, ".");
    else if (slash == path) snprintf(folder, sizeof folder, "/");
    else snprintf(folder, sizeof folder, "%.*s", (int)(slash - path), path);
    if (realpath(folder, real) != NULL)
        snprintf(out, size, "%s/%s", strcmp(real, "/") == 0 ? "" : real, base);
    else
        snprintf(out, size, "%s", path);
}

/* The name `path` resolves to, for a file that need not exist: symbolic links at the last
 * component followed (up to 40), the folder resolved by realpath, then "/" and the last
 * component. A folder that does not exist leaves the path as it is. */
static void resolved_name(const char *path, char *out, size_t size)
{
    char current[2 * PATH_MAX + 2], target[PATH_MAX], folder[2 * PATH_MAX + 2];
    const char *slash;
    snprintf(current, sizeof current, "%s", path);
    for (int depth = 0; depth < 40; ++depth) {
        struct stat st;
        ssize_t n;
        if (lstat(current, &st) != 0 || !S_ISLNK(st.st_mode)) break;
        n = readlink(current, target, sizeof target - 1);
        if (n < 0) break;
        target[n] = '\0';
        slash = strrchr(current, '/');
        if (target[0] == '/' || slash == NULL) snprintf(current, sizeof current, "%s", target);
        else {
            snprintf(folder, sizeof folder, "%.*s", (int)(slash - current), current);
            snprintf(current, sizeof current, "%s/%s", folder, target);
        }
    }
    entry_name(current, out, size);
}

/* *same = 1 when `a` and `b` name one file. A path whose `*_entry` flag is set stands for its
 * folder entry (a temporary file: removed and created anew, never followed; entry_name); the
 * others for the file they lead to: equal device and inode when both exist (links followed),
 * else equal resolved names (resolved_name, realpath for an existing file). Always 0. */
int ffrf_same_file(const char *a, const char *b, int a_entry, int b_entry, int *same)
{
    struct stat sa, sb;
    int has_a = stat(a, &sa) == 0, has_b = stat(b, &sb) == 0;
    char ra[3 * PATH_MAX], rb[3 * PATH_MAX];
    *same = 0;
    if (!a_entry && !b_entry && has_a && has_b) {
        *same = sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
        return 0;
    }
    if (a_entry) entry_name(a, ra, sizeof ra);
    else if (!has_a || realpath(a, ra) == NULL) resolved_name(a, ra, sizeof ra);
    if (b_entry) entry_name(b, rb, sizeof rb);
    else if (!has_b || realpath(b, rb) == NULL) resolved_name(b, rb, sizeof rb);
    *same = strcmp(ra, rb) == 0;
    return 0;
}

/* ---- issue 23, item 6: a run the Fortran runtime ends ----
 * An ALLOCATE without STAT= (or an allocation on assignment) that finds no memory makes the
 * gfortran runtime print one line ("Error allocating N bytes: Cannot allocate memory") and
 * call exit(1). While the guard is on (the driver turns it on once the command line is read
 * and off on its own way out), an exit that does not come from the driver is such an end:
 * the handler adds one "ffrf: error:" line and ends the process with exit status 4. */
static volatile int exit_guard_on = 0;

static void guarded_exit(void)
{
    static const char message[] = "ffrf: error: the run was ended by the Fortran runtime (the "
        "line above; an allocation that found no memory): raise the memory or address-space "
        "limit (ulimit -v), or make the model smaller\n";
    if (!exit_guard_on) return;
    if (write(STDERR_FILENO, message, sizeof message - 1) < 0) _exit(4);
    _exit(4);
}

void ffrf_exit_guard(int on)
{
    static int registered = 0;
    if (on && !registered) registered = atexit(guarded_exit) == 0;
    exit_guard_on = on;
}
