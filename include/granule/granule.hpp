#pragma once
// granule: header-only discrete element method for 2D disks and 3D spheres.
// Umbrella header: the engine, every contact law, walls and the neighbour searches.
#include "granule/boundaries/body.hpp"
#include "granule/boundaries/kinematics.hpp"
#include "granule/boundaries/wall.hpp"
#include "granule/contact/model.hpp"
#include "granule/integrators/symplectic_euler.hpp"
#include "granule/integrators/velocity_verlet.hpp"
#include "granule/core/dimension.hpp"
#include "granule/core/error.hpp"
#include "granule/materials/material.hpp"
#include "granule/materials/material_table.hpp"
#include "granule/materials/time_step.hpp"
#include "granule/neighbours/domain.hpp"
#include "granule/neighbours/policies.hpp"
#include "granule/particles/particle_store.hpp"
#include "granule/simulation.hpp"
