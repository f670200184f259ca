// Umbrella header: everything in slamkit's public API.
#pragma once

#include "slamkit/core/error.h"
#include "slamkit/core/factor_graph.h"
#include "slamkit/core/information.h"
#include "slamkit/core/jacobian_check.h"
#include "slamkit/core/pose_graph.h"
#include "slamkit/core/pose_graph_error.h"
#include "slamkit/factors/between_factor.h"
#include "slamkit/factors/pose_graph_optimizer.h"
#include "slamkit/factors/pose_point_factor.h"
#include "slamkit/factors/prior_factor.h"
#include "slamkit/geometry/se2.h"
#include "slamkit/geometry/se3.h"
#include "slamkit/sim/pose_graph_generator.h"
#include "slamkit/solvers/optimizer.h"
#include "slamkit/solvers/pose_graph_init.h"
