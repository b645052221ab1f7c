// What one job may ask of the farm (docs/security.md, "Limits"). Every limit is a server flag
// with an environment variable; a job over one is refused at submit with INVALID_ARGUMENT (or
// RESOURCE_EXHAUSTED for the queue) and a one-line reason naming the limit and its flag.
#pragma once

#include <cstdint>

#include "job/job_options.h"
#include "scene/scene.h"
#include "tessera/v1/job.pb.h"
#include "wire/scene_bundle.h"

namespace tessera::server {

struct FarmLimits {
  /// Samples per pixel (--max-spp), image width and height (--max-image-size), tile size
  /// (--max-tile): checked by resolve_job_options.
  JobLimits job;
  uint64_t max_bundle_bytes = uint64_t(512)
                              << 20;    ///< sum of the bundle's file sizes (--max-bundle-mb)
  uint64_t max_bundle_files = 10'000;   ///< files in a bundle (--max-bundle-files)
  uint64_t max_triangles = 50'000'000;  ///< triangles in a scene (--max-triangles)
  /// Unfinished (queued or running) jobs one client may have (--max-queued-jobs); 0 = no limit.
  uint64_t max_queued_jobs_per_client = 100;
  /// Work units (tiles x batches) one job may have (--max-units).
  uint64_t max_units_per_job = 1'000'000;
  /// Pixels (width x height) one job may have (--max-pixels). The server holds a job's whole
  /// image when it writes the output files and when it answers a preview (the merged tiles as
  /// stored, the image, the encoded files), so this bounds its memory per job: an 8192 x 8192
  /// job at 1 spp peaked at 4.4 GiB of server memory (docs/security.md, "Limits"); 8K UHD fits.
  uint64_t max_pixels_per_job = uint64_t(8192) * 8192;
  /// Samples of one work unit, tile pixels x the batch's samples per pixel
  /// (--max-unit-samples). A worker finishes the unit in hand on its first SIGTERM, so this
  /// bounds how long that takes: 2^28 is 256 default units (default_batch_spp aims at 2^20),
  /// about half a minute of an 8-core worker on the Cornell box (a million samples per second
  /// per thread, BENCHMARKS.md).
  uint64_t max_unit_samples = uint64_t(1) << 28;
};

/// The job's work units (tiles x batches of its schedule) against --max-units, computed without
/// building the plan's tiles. Throws FarmError(invalid_argument) with one line giving the count
/// and the cap.
void check_unit_count(const JobOptions& options, const FarmLimits& limits);

/// The job's width x height against --max-pixels. Throws FarmError(invalid_argument) with one
/// line giving the count and the cap.
void check_pixel_count(const JobOptions& options, const FarmLimits& limits);

/// The job's largest work unit (a full tile's pixels x its largest batch) against
/// --max-unit-samples. Throws FarmError(invalid_argument) with one line giving the numbers and
/// the cap.
void check_unit_samples(const JobOptions& options, const FarmLimits& limits);

/// Bundle size and file count, on the request as received (before anything is copied).
/// Throws FarmError(invalid_argument).
void check_bundle_limits(const v1::SceneBundle& bundle, const FarmLimits& limits);

/// The triangles the bundle's mesh files declare, counted before they are parsed (so a PLY
/// header declaring 10^8 faces is refused without reading or allocating them): a PLY file counts
/// its header's face count, an OBJ file its "f" lines. Throws FarmError(invalid_argument).
void check_declared_triangles(const wire::BundleContents& bundle, const FarmLimits& limits);

/// The parsed scene's triangles (meshes after triangulation, inline triangles, boxes, quads)
/// and curve segments (a linear curve of n points has n - 1, a B-spline n - 3), together.
/// Throws FarmError(invalid_argument).
void check_scene_triangles(const Scene& scene, const FarmLimits& limits);

}  // namespace tessera::server
