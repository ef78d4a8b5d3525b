// Everything a program embedding pbs calls, in one include: load or generate a scene and analyse its
// hierarchy, surfelize it, read .surfels files, render a frame in any mode, compare images, evaluate a
// sweep of settings against a converged reference.
#pragma once

#include "pbs/evaluation/eval_outputs.hpp"
#include "pbs/evaluation/eval_run.hpp"
#include "pbs/evaluation/eval_settings.hpp"
#include "pbs/evaluation/eval_sources.hpp"
#include "pbs/raster/flip.hpp"
#include "pbs/raster/image_metrics.hpp"
#include "pbs/raster/orbit_camera.hpp"
#include "pbs/scene/find_node.hpp"
#include "pbs/scene/generate.hpp"
#include "pbs/scene/hierarchy.hpp"
#include "pbs/scene/load_scene.hpp"
#include "pbs/surfels/frame_renderer.hpp"
#include "pbs/surfels/surfel_cache.hpp"
#include "pbs/surfels/surfel_file.hpp"
#include "pbs/surfels/surfel_merge.hpp"
#include "pbs/surfels/surfelize.hpp"
#include "pbs/version.hpp"
