#include <sys/ioctl.h>

#include <cerrno>

#include "v4l2_internal.h"

namespace tlvlink::capture::internal {

int xioctl(int fd, unsigned long request, void* arg) {
  int rc;
  do rc = ::ioctl(fd, request, arg);
  while (rc < 0 && errno == EINTR);
  return rc < 0 ? errno : 0;
}

}  // namespace tlvlink::capture::internal
