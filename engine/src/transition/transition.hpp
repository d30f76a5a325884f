// The transition room: forward dynamics and the step differentiated (step_derivatives.cpp): the
// chain rule through M^-1, the passive forces, the actuators and the limit rows, then Euler, RK4
// and the implicit step, in qpos's tangent space. Its public face is lever/derivatives.hpp
// (forward_derivatives, step_derivatives); it reads the derivatives room's RNEA derivatives and
// runs the pipeline's forward(). Nothing here is shared with another room.
#pragma once

#include <lever/derivatives.hpp>
