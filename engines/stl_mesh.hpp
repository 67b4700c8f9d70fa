#pragma once
// ASCII STL surfaces of the layout's solids, for engines that take walls as
// triangle meshes (LIGGGHTS's fix mesh/surface). A mesh wall is met from either
// side, so only the faces grains can reach are written; curved surfaces are
// polygons fine enough that the flat facets stand no further than a stated
// sagitta from the true surface.

#include "engines/apparatus_layout.hpp"

#include <string>

namespace demcal::engines {

// The four faces of a block normal to x and z (its y faces lie on the slab's
// periodic boundaries).
std::string block_stl(const SolidBlock& block);

// A slanted plate's four faces normal to the x-z plane (bottom, top and the two
// slanted sides), spanning y_lower_m..y_upper_m.
std::string slanted_plate_stl(const SlantedPlate& plate, double y_lower_m, double y_upper_m);

// The lateral surface of a cylinder or cone frustum about the z axis, as
// `segments` quads (each two triangles).
std::string axial_shell_stl(const AxialShell& shell, int segments);

// A closed disc about the z axis: its top and bottom faces and its rim.
std::string axial_disc_stl(const AxialDisc& disc, int segments);

// A plate with a circular hole about the z axis, closed: its top and bottom
// rings, the hole's wall and the outer rim.
std::string axial_annulus_stl(const AxialAnnulus& annulus, int segments);

// The number of sides of a polygon inscribed in a circle of this radius whose
// sagitta r (1 - cos(pi / N)) stays within max_sagitta_m; at least 24.
int polygon_segments(double radius_m, double max_sagitta_m);

}  // namespace demcal::engines
