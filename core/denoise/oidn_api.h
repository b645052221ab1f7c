// The part of Intel Open Image Denoise's C API (OpenImageDenoise/oidn.h, version 2) that Tessera
// calls, written from its documentation: the library is loaded at run time (oidn_library.h), so
// these are the functions' types, resolved by name with dlsym, not declarations to link against.
// OIDN's headers are not needed to build Tessera.
#pragma once

#include <cstddef>

namespace tessera::oidn {

using Device = struct DeviceImpl*;  ///< OIDNDevice
using Filter = struct FilterImpl*;  ///< OIDNFilter

/// OIDNDeviceType: OIDN_DEVICE_TYPE_CPU.
inline constexpr int kDeviceTypeCpu = 1;
/// OIDNFormat: OIDN_FORMAT_FLOAT3 (three 32-bit floats per pixel).
inline constexpr int kFormatFloat3 = 3;
/// OIDNError: OIDN_ERROR_NONE.
inline constexpr int kErrorNone = 0;

using NewDeviceFn = Device (*)(int type);
using CommitDeviceFn = void (*)(Device device);
using ReleaseDeviceFn = void (*)(Device device);
/// Returns the first error since the last call (kErrorNone if none) and its message.
using GetDeviceErrorFn = int (*)(Device device, const char** message);
using GetDeviceIntFn = int (*)(Device device, const char* name);
using SetDeviceIntFn = void (*)(Device device, const char* name, int value);
using NewFilterFn = Filter (*)(Device device, const char* type);
/// An image in the caller's memory: name ("color", "albedo", "normal", "output"), pointer,
/// format, width, height, byte offset, pixel stride and row stride (0 = packed).
using SetSharedFilterImageFn = void (*)(Filter filter, const char* name, void* pointer, int format,
                                        size_t width, size_t height, size_t byte_offset,
                                        size_t pixel_byte_stride, size_t row_byte_stride);
using SetFilterBoolFn = void (*)(Filter filter, const char* name, bool value);
using CommitFilterFn = void (*)(Filter filter);
using ExecuteFilterFn = void (*)(Filter filter);
using ReleaseFilterFn = void (*)(Filter filter);

/// Every function Tessera calls, resolved from one loaded library.
struct Api {
  NewDeviceFn new_device = nullptr;                  ///< oidnNewDevice
  CommitDeviceFn commit_device = nullptr;            ///< oidnCommitDevice
  ReleaseDeviceFn release_device = nullptr;          ///< oidnReleaseDevice
  GetDeviceErrorFn get_device_error = nullptr;       ///< oidnGetDeviceError
  GetDeviceIntFn get_device_int = nullptr;           ///< oidnGetDeviceInt
  SetDeviceIntFn set_device_int = nullptr;           ///< oidnSetDeviceInt
  NewFilterFn new_filter = nullptr;                  ///< oidnNewFilter
  SetSharedFilterImageFn set_shared_filter_image = nullptr;  ///< oidnSetSharedFilterImage
  SetFilterBoolFn set_filter_bool = nullptr;         ///< oidnSetFilterBool
  CommitFilterFn commit_filter = nullptr;            ///< oidnCommitFilter
  ExecuteFilterFn execute_filter = nullptr;          ///< oidnExecuteFilter
  ReleaseFilterFn release_filter = nullptr;          ///< oidnReleaseFilter
};

}  // namespace tessera::oidn
