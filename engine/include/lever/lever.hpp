// lever/lever.hpp: everything a lesson needs, in one include.
#pragma once

#include <lever/collision.hpp>
#include <lever/constraint.hpp>
#include <lever/contact_force.hpp>
#include <lever/data.hpp>
#include <lever/derivatives.hpp>
#include <lever/dynamics.hpp>
#include <lever/error.hpp>
#include <lever/fields.hpp>
#include <lever/forward.hpp>
#include <lever/kinematics.hpp>
#include <lever/model.hpp>
#include <lever/model_check.hpp>
#include <lever/parameters.hpp>
#include <lever/regressor.hpp>
#include <lever/spatial.hpp>
#include <lever/spectra.hpp>
#include <lever/version.hpp>
