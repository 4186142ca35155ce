// Versions, status names and the per-thread error message.
#include "capi_internal.h"

namespace facesr::capi {
namespace {

thread_local std::string last_error;

}  // namespace

facesr_status fail(facesr_status status, const char* fn, const std::string& message) noexcept {
  try {
    last_error.assign(fn).append(": ").append(message);
  } catch (...) {
    // Short enough for the small-string buffer: assigning it cannot allocate.
    last_error = "out of memory";
  }
  return status;
}

facesr_status wrong_count(const char* fn, const char* what, int64_t given, int64_t required,
                          const char* rule) noexcept {
  try {
    return fail(FACESR_ERROR_BUFFER_SIZE, fn,
                std::string(what) + " has " + std::to_string(given) + " elements; " + std::to_string(required) + " (" +
                    rule + ") are required");
  } catch (...) {
    return fail(FACESR_ERROR_BUFFER_SIZE, fn, "wrong buffer size");
  }
}

facesr_status null_argument(const char* fn, const char* what) noexcept {
  try {
    return fail(FACESR_ERROR_NULL_ARGUMENT, fn, std::string(what) + " is NULL");
  } catch (...) {
    return fail(FACESR_ERROR_NULL_ARGUMENT, fn, "NULL argument");
  }
}

facesr_status def_too_small(const char* fn, const char* type, uint32_t struct_size, size_t v1_size) noexcept {
  try {
    return fail(FACESR_ERROR_INVALID_ARGUMENT, fn,
                std::string(type) + ".struct_size is " + std::to_string(struct_size) + ", at least " +
                    std::to_string(v1_size) + " is needed (set it to sizeof(" + type +
                    "), or start from facesr_default_*)");
  } catch (...) {
    return fail(FACESR_ERROR_INVALID_ARGUMENT, fn, "struct_size too small");
  }
}

facesr_status check_info_size(const char* fn, const char* type, uint32_t struct_size) noexcept {
  if (struct_size >= sizeof(uint32_t)) return FACESR_OK;
  try {
    return fail(
        FACESR_ERROR_INVALID_ARGUMENT, fn,
        std::string(type) + ".struct_size is " + std::to_string(struct_size) + "; set it to sizeof(" + type + ")");
  } catch (...) {
    return fail(FACESR_ERROR_INVALID_ARGUMENT, fn, "bad struct_size");
  }
}

}  // namespace facesr::capi

extern "C" {

uint32_t facesr_abi_version(void) { return FACESR_ABI_VERSION; }

const char* facesr_version_string(void) { return "facesr " FACESR_VERSION; }

const char* facesr_last_error_message(void) { return facesr::capi::last_error.c_str(); }

const char* facesr_status_name(facesr_status status) {
  // Indexed by the FACESR_* codes, which are 0, 1, ... without gaps.
  static const char* const names[] = {"FACESR_OK",
                                      "FACESR_ERROR_NULL_ARGUMENT",
                                      "FACESR_ERROR_INVALID_ARGUMENT",
                                      "FACESR_ERROR_BUFFER_SIZE",
                                      "FACESR_ERROR_FILE",
                                      "FACESR_ERROR_MISMATCH",
                                      "FACESR_ERROR_DEVICE",
                                      "FACESR_ERROR_NOT_FOUND",
                                      "FACESR_ERROR_STATE",
                                      "FACESR_ERROR_SIMULATION",
                                      "FACESR_ERROR_INTERNAL"};
  static_assert(sizeof names / sizeof names[0] == FACESR_ERROR_INTERNAL + 1, "a status without a name");
  return status >= 0 && status <= FACESR_ERROR_INTERNAL ? names[status] : "unknown";
}

}  // extern "C"
