// A lat-long environment map in memory and its importance-sampling tables.
#pragma once

#include <vector>

#include "renderer/core/angle_table.h"
#include "renderer/core/distribution.h"
#include "scene/scene.h"

namespace kiln {

// A point of the map drawn by importance: its (u, v), direction, density and texel (its radiance:
// EnvironmentMap::radianceAt).
struct EnvironmentSample {
    float u = 0, v = 0;
    Vec3 dir;
    float pdf = 0;          // solid angle
    size_t iu = 0, iv = 0;  // the texel drawn
    float pdfV = 0;         // the row's density (pickRow)
};

// A lat-long environment map in memory (scaled, in the working space), looked up bilinearly
// (nearest texel for scenes built without the loader), with its importance-sampling tables: a row
// by inversion of the rows' marginal, then a column by inversion of the row's own distribution
// (guide tables: expected O(1), one 16-byte read in the common case). Inversion keeps the
// sampler's stratification: an alias table for the columns (one read always) had 1.16-1.25x the
// error at equal samples on the env-lit Lucy.
struct EnvironmentMap {
    int width = 0, height = 0;
    std::vector<Color> pixels;
    Color constant{0.0f};        // used when there is no image (uniform environment)
    Distribution1D rows;         // by each row's total weight
    Distribution1DRows columns;  // within each row
    float scale = 1;
    float rotation = 0;     // radians about +Y (right-handed: counterclockwise seen from above)
    bool bilinear = false;  // between texel centres (the loader's maps); else nearest texel
    // Sampled by the light above a share of the map's mean (MIS compensation, only for renders
    // that weigh every map sample against BSDF sampling by MIS), and some lit texels cut to 0:
    // light sampling alone would miss their light.
    bool compensated = false;
    // sin, cos of theta = v pi and of phi = (u - 0.5) 2 pi - rotation.
    AngleTable theta{0.0, 3.14159265358979323846, 128};
    AngleTable phi{-3.14159265358979323846, 2 * 3.14159265358979323846, 256};

    Color lookup(const Vec3& dir) const;
    Color lookup(float u, float v) const;          // (u, v) in [0,1)^2
    Color bilinearLookup(float u, float v) const;  // (u, v) in [0,1)^2
    // The four texels a bilinear lookup at (u, v) blends, and its weights.
    struct BilinearTexels {
        int x0, x1, y0, y1;
        float tx, ty;
    };
    BilinearTexels bilinearTexels(float u, float v) const;
    Vec3 direction(float u, float v) const;  // (u, v) in [0,1)^2 -> unit direction
    void coordinates(const Vec3& dir, float& u, float& v) const;
    // The same from dir's coordinates found already (latLong4: rays leaving a batch, four at once).
    void coordinates(const LatLong& dirLatLong, float& u, float& v) const;
    // Asks memory for the first table entry locate(u1, u2) reads (the row's is in cache).
    void prefetch(float u1, float u2) const;
    // Importance sampling (a map with pixels) in two steps: the point and its density (its texels
    // asked for from memory; false where it has no density), then its radiance; between them the
    // texels' cache misses can overlap other work.
    bool locate(float u1, float u2, EnvironmentSample& out) const;
    // locate in two parts: the row (v, iv, pdfV), with the column's first table entry asked for
    // from memory as prefetch does, then the rest of the point: locate(u1, u2) bit for bit, and a
    // caller that prefetches early keeps the row instead of drawing it twice.
    void pickRow(float u1, float u2, EnvironmentSample& out) const;
    bool locateInRow(float u1, EnvironmentSample& out) const;
    Color radianceAt(const EnvironmentSample& s) const;
    // Asks memory for what lookup(u, v) and pdf(u, v, .) read: a batch's escaped rays, whose
    // texels and table entries are misses on a map larger than the cache, overlap them.
    void prefetchLookup(float u, float v) const;
    // Asks memory for the texels lookup(u, v) reads, texel (iu, iv) holding (u, v).
    void prefetchTexels(float u, float v, size_t iu, size_t iv) const;
    // Solid-angle density of locate() drawing the unit direction dir.
    float pdf(const Vec3& dir) const;
    // The same at dir's own coordinates (u, v), as coordinates() gives them.
    float pdf(float u, float v, const Vec3& dir) const;
};

// The light's map in memory: scaled, non-finite and negative texels zeroed, with its sampling
// tables (a uniform environment when the light has no image), MIS-compensated if asked.
EnvironmentMap loadEnvironment(const Light& l, bool misCompensated = false);

}  // namespace kiln
