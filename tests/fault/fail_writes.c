/* Fault injection for the reliability tests: an LD_PRELOAD shim that makes writes fail the way a
 * full disk does, on the files a test names, after a given number of bytes.
 *
 *   CONTACTSWEEP_FAULT_PATH   the end of the paths (/proc/self/fd) of the files to fail, e.g.
 *                             ".h5.partial" (the HDF5 file) or ".bin.tmp" (journal blocks)
 *   CONTACTSWEEP_FAULT_AFTER  bytes that may still be written to those files, summed over this
 *                             process (default 0); every write after that fails
 *   CONTACTSWEEP_FAULT_ERRNO  the error (default ENOSPC = 28)
 *   CONTACTSWEEP_FAULT_RESERVE  if set, the most bytes posix_fallocate may reserve for those
 *                             files (a quota); unset, reservations are never refused
 *
 *   CONTACTSWEEP_FAULT_LOCK   the end of the paths of files whose lock requests fail with ENOLCK
 *                             (a file system without locks: an NFS mount without lockd)
 *
 * It wraps write, pwrite, pwrite64, writev, pwritev and pwritev64: what HDF5's MPI-IO driver
 * (Open MPI's fbtl) and our journal call. Writes to other files pass through untouched. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>
#include <sys/uio.h>
#include <unistd.h>

static atomic_llong budget = -1; /* -1: not read yet */

static long long remaining_budget(void) {
  long long b = atomic_load(&budget);
  if (b >= 0) return b;
  const char* after = getenv("CONTACTSWEEP_FAULT_AFTER");
  atomic_store(&budget, after ? atoll(after) : 0);
  return atomic_load(&budget);
}

static int path_ends_with(int fd, const char* pattern) {
  if (pattern == NULL || *pattern == '\0') return 0;
  char link[64], path[PATH_MAX];
  snprintf(link, sizeof link, "/proc/self/fd/%d", fd);
  ssize_t n = readlink(link, path, sizeof path - 1);
  if (n <= 0) return 0;
  path[n] = '\0';
  size_t length = strlen(pattern);
  return (size_t)n >= length && strcmp(path + n - length, pattern) == 0;
}

static int selected(int fd) { return path_ends_with(fd, getenv("CONTACTSWEEP_FAULT_PATH")); }

static int fault_errno(void) {
  const char* e = getenv("CONTACTSWEEP_FAULT_ERRNO");
  return e ? atoi(e) : ENOSPC;
}

/* How many of `count` bytes may be written to `fd`: count, fewer (a short write), or -1 with
 * errno set (the disk is full). */
static ssize_t allowed(int fd, size_t count) {
  if (count == 0 || !selected(fd)) return (ssize_t)count;
  long long left = remaining_budget();
  for (;;) {
    if (left <= 0) {
      errno = fault_errno();
      return -1;
    }
    long long take = (long long)count < left ? (long long)count : left;
    if (atomic_compare_exchange_weak(&budget, &left, left - take)) return (ssize_t)take;
  }
}

typedef ssize_t (*write_fn)(int, const void*, size_t);
typedef ssize_t (*pwrite_fn)(int, const void*, size_t, off_t);
typedef ssize_t (*pwrite64_fn)(int, const void*, size_t, off64_t);
typedef ssize_t (*writev_fn)(int, const struct iovec*, int);
typedef ssize_t (*pwritev_fn)(int, const struct iovec*, int, off_t);
typedef ssize_t (*pwritev64_fn)(int, const struct iovec*, int, off64_t);

#define REAL(name) static name##_fn real_##name = NULL; \
  if (!real_##name) real_##name = (name##_fn)dlsym(RTLD_NEXT, #name)

ssize_t write(int fd, const void* buf, size_t count) {
  REAL(write);
  ssize_t n = allowed(fd, count);
  return n < 0 ? -1 : real_write(fd, buf, (size_t)n);
}

ssize_t pwrite(int fd, const void* buf, size_t count, off_t offset) {
  REAL(pwrite);
  ssize_t n = allowed(fd, count);
  return n < 0 ? -1 : real_pwrite(fd, buf, (size_t)n, offset);
}

ssize_t pwrite64(int fd, const void* buf, size_t count, off64_t offset) {
  REAL(pwrite64);
  ssize_t n = allowed(fd, count);
  return n < 0 ? -1 : real_pwrite64(fd, buf, (size_t)n, offset);
}

static size_t total(const struct iovec* iov, int iovcnt) {
  size_t sum = 0;
  for (int i = 0; i < iovcnt; ++i) sum += iov[i].iov_len;
  return sum;
}

/* Vector writes fail whole or pass whole: a short vector write is rare enough not to model. */
static int vector_refused(int fd, const struct iovec* iov, int iovcnt) {
  size_t want = total(iov, iovcnt);
  ssize_t n = allowed(fd, want);
  if (n >= 0 && (size_t)n < want) errno = fault_errno();
  return n < 0 || (size_t)n < want;
}

ssize_t writev(int fd, const struct iovec* iov, int iovcnt) {
  REAL(writev);
  return vector_refused(fd, iov, iovcnt) ? -1 : real_writev(fd, iov, iovcnt);
}

ssize_t pwritev(int fd, const struct iovec* iov, int iovcnt, off_t offset) {
  REAL(pwritev);
  return vector_refused(fd, iov, iovcnt) ? -1 : real_pwritev(fd, iov, iovcnt, offset);
}

ssize_t pwritev64(int fd, const struct iovec* iov, int iovcnt, off64_t offset) {
  REAL(pwritev64);
  return vector_refused(fd, iov, iovcnt) ? -1 : real_pwritev64(fd, iov, iovcnt, offset);
}

/* A quota the free-space figures do not show (durable_file.cpp, check_room_for): with
 * CONTACTSWEEP_FAULT_RESERVE set, reserving more than that many bytes of a chosen file fails
 * with CONTACTSWEEP_FAULT_ERRNO. Unset, reservations pass through, so that the cases above fail
 * in the writes they name. posix_fallocate returns the error; it does not set errno. */
typedef int (*posix_fallocate_fn)(int, off_t, off_t);
typedef int (*posix_fallocate64_fn)(int, off64_t, off64_t);

static int reserve_refused(int fd, long long length) {
  const char* most = getenv("CONTACTSWEEP_FAULT_RESERVE");
  return most != NULL && selected(fd) && length > atoll(most);
}

int posix_fallocate(int fd, off_t offset, off_t length) {
  REAL(posix_fallocate);
  return reserve_refused(fd, (long long)length) ? fault_errno() : real_posix_fallocate(fd, offset, length);
}

int posix_fallocate64(int fd, off64_t offset, off64_t length) {
  REAL(posix_fallocate64);
  return reserve_refused(fd, (long long)length) ? fault_errno() : real_posix_fallocate64(fd, offset, length);
}

/* A file system without locks: with CONTACTSWEEP_FAULT_LOCK set, a lock request (F_OFD_SETLK,
 * F_SETLK) on a file whose path ends with it fails with ENOLCK; every other call passes. */
typedef int (*fcntl_fn)(int, int, ...);

int fcntl(int fd, int cmd, ...) {
  REAL(fcntl);
  va_list ap;
  va_start(ap, cmd);
  void* arg = va_arg(ap, void*);  /* an int or a pointer: passed on as glibc's own fcntl does */
  va_end(ap);
  if ((cmd == F_OFD_SETLK || cmd == F_SETLK) &&
      path_ends_with(fd, getenv("CONTACTSWEEP_FAULT_LOCK"))) {
    errno = ENOLCK;
    return -1;
  }
  return real_fcntl(fd, cmd, arg);
}
