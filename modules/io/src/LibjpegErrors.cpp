// A corrupt JPEG inside a rawlog must be an error, not the end of the process (found
// by fuzz_rawlog): MRPT 2.5's CImage::loadFromStreamAsJPEG (images stored as JPEG in a rawlog)
// keeps libjpeg's default error manager, whose error_exit prints the message and calls exit(1),
// so `rasm run` died without a report. This definition of jpeg_std_error interposes libjpeg's
// for the whole process (rasm_io is loaded before libjpeg; MRPT calls it through the PLT): it
// calls the real one and makes error_exit throw instead. Callers that install their own
// error_exit afterwards (OpenCV's decoder) are unaffected. tests/io/RawlogFrameSource_unittest.cpp.
#include <dlfcn.h>

#include <cstdio>
#include <stdexcept>
#include <string>

extern "C" {
#include <jpeglib.h>
}

namespace {

using StdErrorFn = jpeg_error_mgr* (*)(jpeg_error_mgr*);

[[noreturn]] void throwingErrorExit(j_common_ptr cinfo) {
  char msg[JMSG_LENGTH_MAX] = "";
  (*cinfo->err->format_message)(cinfo, msg);
  // The caller never gets back to its jpeg_destroy_decompress (the exception unwinds past it):
  // free the object's memory pools here, or every corrupt image leaks ~6 KB (LeakSanitizer,
  // scripts/asan.sh). The error manager itself belongs to the caller and is not touched.
  jpeg_destroy(cinfo);
  throw std::runtime_error(std::string("corrupt JPEG image: ") + msg);
}

}  // namespace

extern "C" jpeg_error_mgr* jpeg_std_error(jpeg_error_mgr* err) {
  static const auto real = reinterpret_cast<StdErrorFn>(dlsym(RTLD_NEXT, "jpeg_std_error"));
  if (!real) {
    std::fprintf(stderr, "rasm: libjpeg's jpeg_std_error not found\n");
    throw std::runtime_error("libjpeg's jpeg_std_error not found");
  }
  jpeg_error_mgr* e = real(err);
  e->error_exit = throwingErrorExit;
  return e;
}
