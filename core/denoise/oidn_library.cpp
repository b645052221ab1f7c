#include "denoise/oidn_library.h"

#include <dlfcn.h>

#include <cstdlib>

namespace tessera {
namespace {

/// Resolves `name` into `fn`; returns false when the library lacks it.
template <typename Fn>
bool resolve(void* handle, const char* name, Fn& fn) {
  fn = reinterpret_cast<Fn>(dlsym(handle, name));
  return fn != nullptr;
}

/// Every function of oidn::Api from `handle`; "" when all resolved, else the first missing name.
std::string resolve_api(void* handle, oidn::Api& api) {
  struct Entry {
    const char* name;
    bool ok;
  };
  const Entry entries[] = {
      {"oidnNewDevice", resolve(handle, "oidnNewDevice", api.new_device)},
      {"oidnCommitDevice", resolve(handle, "oidnCommitDevice", api.commit_device)},
      {"oidnReleaseDevice", resolve(handle, "oidnReleaseDevice", api.release_device)},
      {"oidnGetDeviceError", resolve(handle, "oidnGetDeviceError", api.get_device_error)},
      {"oidnGetDeviceInt", resolve(handle, "oidnGetDeviceInt", api.get_device_int)},
      {"oidnSetDeviceInt", resolve(handle, "oidnSetDeviceInt", api.set_device_int)},
      {"oidnNewFilter", resolve(handle, "oidnNewFilter", api.new_filter)},
      {"oidnSetSharedFilterImage",
       resolve(handle, "oidnSetSharedFilterImage", api.set_shared_filter_image)},
      {"oidnSetFilterBool", resolve(handle, "oidnSetFilterBool", api.set_filter_bool)},
      {"oidnCommitFilter", resolve(handle, "oidnCommitFilter", api.commit_filter)},
      {"oidnExecuteFilter", resolve(handle, "oidnExecuteFilter", api.execute_filter)},
      {"oidnReleaseFilter", resolve(handle, "oidnReleaseFilter", api.release_filter)},
  };
  for (const Entry& e : entries) {
    if (!e.ok) return e.name;
  }
  return "";
}

}  // namespace

std::vector<std::string> oidn_library_candidates(const std::string& named,
                                                 const std::string& configured) {
  if (!named.empty()) return {named};
  std::vector<std::string> candidates;
  if (!configured.empty()) candidates.push_back(configured);
  candidates.emplace_back(kOidnSoname);
  return candidates;
}

std::string named_oidn_library(const std::string& flag) {
  if (!flag.empty()) return flag;
  const char* env = std::getenv("TESSERA_OIDN_LIBRARY");
  return env != nullptr ? env : "";
}

std::string configured_oidn_library() { return TESSERA_OIDN_CONFIGURED_LIBRARY; }

std::shared_ptr<const OidnLibrary> OidnLibrary::load(const std::vector<std::string>& candidates) {
  std::string tried;
  for (const std::string& path : candidates) {
    // RTLD_LOCAL: OIDN's symbols stay out of the global namespace. Its CPU device finds the
    // bundled TBB through its own run path, or shares the process's libtbb.so.12 when one is
    // already loaded (the worker's: same ABI).
    void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    std::string why;
    if (handle == nullptr) {
      const char* error = dlerror();
      why = error != nullptr ? error : "cannot be loaded";
    } else {
      oidn::Api api;
      const std::string missing = resolve_api(handle, api);
      if (missing.empty()) return std::make_shared<const OidnLibrary>(api, path);
      why = path + ": no " + missing + " (not Open Image Denoise 2?)";
      dlclose(handle);
    }
    tried += (tried.empty() ? "" : "; ") + why;
  }
  throw DenoiserUnavailable(
      "--denoise needs Intel Open Image Denoise 2 (" + std::string(kOidnSoname) +
      "): run scripts/install-deps.sh, or name the library with --oidn-library PATH or "
      "TESSERA_OIDN_LIBRARY (tried: " + tried + ")");
}

std::vector<std::string> oidn_library_candidates_for_flag(const std::string& flag) {
  return oidn_library_candidates(named_oidn_library(flag), configured_oidn_library());
}

std::shared_ptr<const OidnLibrary> OidnLibrary::load_for_flag(const std::string& flag) {
  return load(oidn_library_candidates_for_flag(flag));
}

}  // namespace tessera
