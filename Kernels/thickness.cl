// BRepThickness: the maximal-sphere solver (Lemasson et al. 2014, sections 2.1-2.3), written
// once. One work-item per chain of samples O (solve_chain), each: BVH initialisation (eq. 1) or
// the previous sample's contact as the start, surface/surface Newton (eq. 4),
// trim test (eq. 6 and the corner rule), surface/edge Newton (eq. 7), the verification against
// s1 and the certification against the patches, with restarts from any point found inside.
// The same source is compiled as OpenCL C (Kernels/OpenCLSolver: float, or double with
// -DBRT_DOUBLE) and as C++ in double (Filters/Core/NativeSolver: the native CPU device and the
// reference), in the common subset of the two languages (Kernels/KernelLanguage.h states its
// rules). Coordinates arrive relative to the model's centre.

#ifdef __OPENCL_VERSION__
#pragma OPENCL FP_CONTRACT OFF
#ifdef BRT_DOUBLE
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
typedef double real;
typedef double2 real2;
typedef double3 real3;
#define REAL_MAX DBL_MAX
#define REAL_MIN DBL_MIN
#define REAL_EPS DBL_EPSILON
#else
typedef float real;
typedef float2 real2;
typedef float3 real3;
#define REAL_MAX FLT_MAX
#define REAL_MIN FLT_MIN
#define REAL_EPS FLT_EPSILON
#endif
#define make_real2(a, b) ((real2)((a), (b)))
#define make_real3(a, b, c) ((real3)((a), (b), (c)))
#define splat_real3(s) ((real3)(s))
#define splat_real2(s) ((real2)(s))
// BRT_SPLIT marks the large functions called from several places: OpenCL compilers keep them as
// functions of their own. NVIDIA's compiler otherwise inlines every call, and the fully inlined
// brt_solve (about 125,000 statements, 0.8 million lines of PTX) keeps its PTX assembler busy
// for many minutes (docs/Solver.md, "Compile time on GPUs"). The C++ build leaves the choice to
// the compiler. Testing/KernelGpuCodeSize.sh measures the code this gives (-DBRT_SPLIT= turns
// the splitting off, to see the difference).
#ifndef BRT_SPLIT
#define BRT_SPLIT __attribute__((noinline))
#endif
#else
// Compiled as C++ (double): Filters/Core/NativeSolver.cxx includes this file inside namespace
// brt::kernel, after KernelLanguage.h.
#define BRT_SPLIT
#endif

// Contact types and failure reasons: same values as brt::ContactType and brt::FailReason.
#define CONTACT_FAILED 0
#define CONTACT_SURFACE_SURFACE 1
#define CONTACT_SURFACE_EDGE 2
#define CONTACT_SURFACE_VERTEX 3
#define CONTACT_OTHER_SOLID 4 // the gap with all solids: O lies on or in another solid (gap 0)
#define CONTACT_OSCULATING 5  // the sphere osculates O's own face at O (osculating_bound)
#define FAIL_NONE 0
#define FAIL_NO_OPPOSITE 1
#define FAIL_NOT_CONVERGED 2
#define FAIL_EDGE_NOT_CONVERGED 3
#define FAIL_NO_EDGE 4
#define FAIL_SINGULAR 5
#define FAIL_LEFT_MODEL 6
#define FAIL_NOT_MAXIMAL 7
#define FAIL_THIN_WALL 11 // the wall across O is thinner than 2 slack (thin_wall_across)
// The s1 tree's root First where it splits the faces' points from the edges' (brt::S1SplitRoot).
#define S1_SPLIT_ROOT (-2)

// Per-face integers (FACE_INTS of them): first patch, patches along u, along v, offset of the
// grid breakpoints, first loop, loop count, reversed (outward normal = -(Su x Sv)), solid, the
// kind of its exact surface (EXACT_*), the root of its trimming segments' tree (-1: none;
// brt::PackTrimTrees), 1 where its patches are its surface (a polynomial B-spline or Bezier of
// degree 3 at most, converted exactly: brt::PatchesAreTheSurface), and on a plane whose patches
// are its isometric parametrisation the sign s of its frame (Y = s (axis x X), X in the exact
// surface's sizes; 0: none; brt::PlaneFrame, plane_trim_gap), then up to WALL_PARTNERS faces
// across its thin walls (-1: none; brt::BuildWallPartners, wall_partner_start).
#define WALL_PARTNERS 8
#define FACE_INTS 20
// Per-face reals: u0, u1, v0, v1, periods in u and v (0: open), UV tolerance, then the exact
// surface (FACE_EXACT on): its origin as hi (3) + lo (3) parts relative to the model's centre, its
// unit axis (3) and three sizes, then the patches' measured deviation from the face (FACE_DEVIATION;
// brt::PackKernelModel), then on a plane with a frame (FACE_INTS slot 11) the measured distance
// between its edges and their trimming segments' images at the same edge parameter
// (FACE_TRIM_EDGE_GAP; brt::PlaneTrimEdgeGap, memo_inside), then -1 where its trimming loops do
// not cross, else a bound on the crossing test's chords' error (FACE_LOOPS_CROSS;
// brt::TrimLoopsCross, classify).
#define FACE_REALS 22
// Per trimming segment: its four (u, v) control points, then their box (u0, v0, u1, v1).
#define TRIM_REALS 12
// Segments per leaf of a face's trim tree at most (brt::PackTrimTrees).
#define TRIM_LEAF 4
#define FACE_EXACT 7
#define FACE_DEVIATION 19
#define FACE_TRIM_EDGE_GAP 20
#define FACE_LOOPS_CROSS 21
// Per patch of a cylindrical face, the sector of the cylinder its control points lie in
// (cylinder_patch_gap); of a toroidal face, its range of angles around the tube and its wedge
// around the axis (torus_patch_gap); of a spherical face, its cone from the centre
// (sphere_patch_gap); of a face with no exact surface, the tube that holds it (tube_patch_gap;
// brt::KernelPatchSectorReals).
#define PATCH_SECTOR_REALS 12
// Reals per patch of its control net's constants: the control points' mean relative to the anchor,
// the unit normal of the net's diagonals, the least and greatest offset of the control points
// along it and the corners' mean's (patch_gap); the diagonal of the box of its 5 x 5 grid's points
// (certify_patch; brt::KernelPatchHullReals).
#define PATCH_HULL_REALS 10
// Exact surfaces of analytic faces (brt::BRepModel::FaceExact), for the exact finish. Sizes:
// plane its frame's X where it has one (FACE_INTS); cylinder radius; cone the radius at the
// origin, cos and sin of the semi-angle; sphere radius; torus major and minor radius.
#define EXACT_NONE 0
#define EXACT_PLANE 1
#define EXACT_CYLINDER 2
#define EXACT_CONE 3
#define EXACT_SPHERE 4
#define EXACT_TORUS 5
// Per sample: O as hi (3) + lo (3) parts relative to the model's centre, the inward normal d (3),
// (u, v) on its face, and the largest curvature of its face at O towards d (0: none known).
#define SAMPLE_REALS 12
// Per result: t, foot - O (3), residual, the foot's parameters (u, v on the face; T, 0 on the
// edge).
#define OUT_REALS 7
// Per result: type, reason, face, patch, edge, iterations, exact pass (0 or 1).
#define OUT_INTS 7

// Model::mode, the launch argument 44 (brt::KernelScalars).
#define MODE_CERTIFY 1    // certify every sphere against the patches (needs a box node)
#define MODE_EXTERIOR 2   // the gap: d is the outward normal, the sphere lies in the air and
                          // touches faces from their outer side (brt::SolverOptions::Exterior)
#define MODE_ALL_SOLIDS 4 // walls of every solid bound the sphere, not only O's own
                          // (brt::SolverOptions::AllSolids)

typedef struct
{
  real3 P, Du, Dv, Duu, Duv, Dvv;
} PatchEval;

// What the samples of a chain learn for the ones after them besides the start (solve_chain):
// disks of (u, v) on isometric planes that lie inside the face's trim, each the disk around a
// foot that the surface Newton's trim test (classify) found inside, of its distance from the
// nearest trimming segment (a thousandth less, for rounding). The next sample's foot on the same
// face mostly falls within it (two thirds of NIST_MBE_PMI_11's plane feet), and the disk answers
// the trim test there (surface_newton). Only speed depends on it: a foot the disk holds gets the
// trim test's answer as classify would give it (docs/Solver.md, item 20, "Chains").
#define MEMO_DISKS 2
typedef struct
{
  int face[MEMO_DISKS]; // -1: empty
  real u[MEMO_DISKS], v[MEMO_DISKS], r[MEMO_DISKS];
  real gap[MEMO_DISKS]; // the face's FACE_TRIM_EDGE_GAP
  int next; // the slot the next new face takes
  // The sample being solved: its face and (u, v) there (solve_sample), so that the certification
  // finds O on its own face's patches without a search (certify_patch).
  int ownFace;
  real ownU, ownV;
} ChainMemo;

typedef struct
{
  __global const real* patches;     // 48 per patch, relative to the patch's anchor
  __global const real* patchAnchor; // 6 per patch: anchor as hi (3) + lo (3) parts
  __global const real* patchDomain; // 4 per patch
  __global const int* faceInfo;     // FACE_INTS per face
  __global const real* faceDomain;  // FACE_REALS per face
  __global const real* breaks;      // grid breakpoints
  __global const int* loops;        // first segment, count per loop
  __global const real* trim;        // TRIM_REALS per trimming segment
  __global const int* trimEdge;     // edge per trimming segment (-1: degenerated)
  __global const real* trimRange;   // T0, T1 per trimming segment
  // Per face with many trimming segments, their BVH in (u, v) (FACE_INTS slot 9 its root): the
  // boxes (u0, v0, u1, v1 per node), (first, count, right) per node (the left child next to its
  // parent), and the leaves' (segment, loop) pairs from first.
  __global const real* trimNodeBox;
  __global const int* trimNodeInfo;
  __global const int* trimItems;
  __global const int* edgeInfo;     // first segment, count, face 0, face 1 per edge
  __global const real* edgeRange;   // T0, T1 and the distance from each face's exact surface (-1: none) per edge
  __global const real* edgeSeg;     // 12 per edge segment, relative to its anchor
  __global const real* edgeAnchor;  // 6 per edge segment: anchor hi (3) + lo (3)
  __global const real* edgeSegRange; // T0, T1 per edge segment
  __global const int* vertexInfo;   // per edge end: its vertex's record (-1: none); a record
                                    // is a count then the ends 2 * edge + k (brt::SolverData)
  real slack; // the patches' accuracy: 2x the conversion tolerance (model units)
  real delta; // the clearance of this pass (brt::SolverOptions::Clearance; 0: eq. 1 exactly)
  real s1Spacing; // the spacing s1 was sampled at (brt::SolverData::S1Spacing)
  // The certification against the patches (brt::SolverOptions::Certify): the control-point boxes
  // of the patches and edge segments (6 each, min then max) and their BVH (brt::SolverData).
  __global const int* patchFace;   // face per patch
  __global const int* edgeSegEdge; // edge per edge segment
  __global const real* patchBoxes;
  __global const real* patchSector; // PATCH_SECTOR_REALS per patch (brt::PackKernelModel)
  __global const real* patchHull;   // PATCH_HULL_REALS per patch (brt::PackKernelModel)
  __global const real* edgeBoxes;
  __global const real* boxNodeBox;  // 6 per node
  __global const int* boxNodeInfo;  // first, count, right per node
  __global const int* boxItems;     // patch p, or edge segment e as patchCount + e
  int patchCount;
  int mode; // MODE_* bits: certification, the exterior (gap) sphere, the walls of all solids
  ChainMemo* memo; // the chain's (solve_chain); 0 outside a chain
} Model;

// The sphere touches `face` from inside: its centre on the material side at the foot (side <= 0),
// or, on a face other than the sample's, at most the clearance plus the patches' error outside
// it. A sample on a convex edge (a mesh vertex on it) lies within the conversion tolerance of
// the face across, possibly on its outer side; its sphere is about the clearance, and touches
// the face across from "outside" by up to that much. A sphere touching a face really from
// outside has its centre t - delta beyond it: only spheres below twice the clearance plus the
// tolerance are affected.
inline int from_inside(const Model* m, int sampleFace, int face, real side)
{
  // The gap's sphere lies in the air: it touches faces from their outer side.
  if (m->mode & MODE_EXTERIOR)
    side = -side;
  return !(side > (face == sampleFace ? (real)0 : m->delta + (real)0.5 * m->slack));
}

// The solid whose walls bound the sphere at a sample on ownFace: its own, or -1 for every solid
// (MODE_ALL_SOLIDS).
inline int scope_solid(const Model* m, int ownFace)
{
  return (m->mode & MODE_ALL_SOLIDS) ? -1 : m->faceInfo[FACE_INTS * ownFace + 7];
}

// A face belongs to the scope (scope_solid).
inline int in_scope(__global const int* faceInfo, int face, int solid)
{
  return solid < 0 || faceInfo[FACE_INTS * face + 7] == solid;
}

// A point P (relative to O) within the patches' accuracy of O.
inline int near_sample(const Model* m, real3 P)
{
  return dot(P, P) <= m->slack * m->slack;
}

// A foot on the sample's own face next to O: the trivial solution P = O of eq. 4
//.
inline int at_sample(const Model* m, int sampleFace, int face, real3 P)
{
  return face == sampleFace && near_sample(m, P);
}

// An edge point next to O on an edge of O's own face: the trivial solution C = O
//.
inline int edge_at_sample(const Model* m, int sampleFace, int edge, real3 C)
{
  const int f0 = m->edgeInfo[4 * edge + 2], f1 = m->edgeInfo[4 * edge + 3];
  return (f0 == sampleFace || f1 == sampleFace) && near_sample(m, C);
}

// A foot next to O on a face whose normal n there is within 2e-3 rad of O's: the trivial
// solution across a tangent edge.
inline int tangent_at_sample(const Model* m, real3 P, real3 n, real3 d)
{
  const real3 c = cross(n, d);
  return near_sample(m, P) && dot(c, c) <= (real)4e-6 * dot(n, n);
}

// A foot point on the sample's own face within the patches' accuracy of O is the trivial
// solution of eq. 4 (P = O solves it for every t), and one shallower than t/2 an osculating
// sphere whose radius the patches' accuracy does not fix: no contact
//. P is relative to O.
inline int shallow_own_face_contact(const Model* m, int sampleFace, int face, real3 P, real3 d,
  real t)
{
  return at_sample(m, sampleFace, face, P) || (face == sampleFace && dot(P, d) < (real)0.5 * t);
}

// A - O for an anchor A and the sample O, both split into hi + lo parts: the difference of two
// nearby large coordinates is formed before it is rounded, so float keeps (t + patch size) * eps
// of accuracy instead of (model size) * eps.
inline real3 anchor_minus(__global const real* a, real3 Ohi, real3 Olo)
{
  return (make_real3(a[0], a[1], a[2]) - Ohi) + (make_real3(a[3], a[4], a[5]) - Olo);
}

inline void bernstein(real t, real* B, real* D, real* DD)
{
  const real s = (real)1 - t;
  B[0] = s * s * s;
  B[1] = (real)3 * s * s * t;
  B[2] = (real)3 * s * t * t;
  B[3] = t * t * t;
  D[0] = (real)-3 * s * s;
  D[1] = (real)3 * s * s - (real)6 * s * t;
  D[2] = (real)6 * s * t - (real)3 * t * t;
  D[3] = (real)3 * t * t;
  DD[0] = (real)6 * s;
  DD[1] = (real)-12 * s + (real)6 * t;
  DD[2] = (real)6 * s - (real)12 * t;
  DD[3] = (real)6 * t;
}

inline int upper_index(__global const real* b, int n, real x)
{
  // Index i in [0, n-1] of the interval [b[i], b[i+1]) holding x (clamped).
  int lo = 0, hi = n - 1;
  while (lo < hi)
  {
    const int mid = (lo + hi + 1) / 2;
    if (x >= b[mid])
      lo = mid;
    else
      hi = mid - 1;
  }
  return lo;
}

inline int find_patch(const Model* m, int face, real u, real v)
{
  __global const int* fi = m->faceInfo + FACE_INTS * face;
  const int nu = fi[1], nv = fi[2];
  __global const real* bu = m->breaks + fi[3];
  __global const real* bv = bu + nu + 1;
  return fi[0] + upper_index(bu, nu, u) + upper_index(bv, nv, v) * nu;
}

// On a plane whose patches are its isometric parametrisation (FACE_INTS slot 11; brt::PlaneFrame
// checks every control point at Q0 + u X + v Y to 1e-12 of the face's size), a patch is affine in
// (u, v): its point is its first control point (at the patch's (u0, v0)) plus (u - u0) X +
// (v - v0) Y, its first derivatives X and Y, its second 0. 1 with the frame in *X, *Y where patch
// p is such a patch. Evaluated so, a plane's patch costs a few operations instead of the tensor
// product's hundreds: the solve's instructions fell by 6-14% on the Data/ parts, its time by 3-14%
// (docs/Solver.md, Benchmark, thirtieth session). The results differ from the tensor product's by
// its rounding, which moves some spheres between admissible contacts (the same docs).
// plane_face_frame: the same for a face (plane_trim_gap).
inline int plane_face_frame(const Model* m, int face, real3* X, real3* Y)
{
  __global const int* fi = m->faceInfo + FACE_INTS * face;
  if (fi[8] != EXACT_PLANE || fi[11] == 0)
    return 0;
  __global const real* e = m->faceDomain + FACE_REALS * face + FACE_EXACT;
  *X = make_real3(e[9], e[10], e[11]);
  *Y = (real)fi[11] * cross(make_real3(e[6], e[7], e[8]), *X);
  return 1;
}

inline int plane_patch_frame(const Model* m, int p, real3* X, real3* Y)
{
  return plane_face_frame(m, m->patchFace[p], X, Y);
}

// The point of patch p at face parameters (u, v) only, relative to the patch's anchor.
real3 eval_patch_point(const Model* m, int p, real u, real v)
{
  __global const real* d = m->patchDomain + 4 * p;
  __global const real* c = m->patches + 48 * p;
  real3 X, Y;
  if (plane_patch_frame(m, p, &X, &Y))
    return make_real3(c[0], c[1], c[2]) + (u - d[0]) * X + (v - d[2]) * Y;
  real Bu[4], Du[4], DDu[4], Bv[4], Dv[4], DDv[4];
  bernstein((u - d[0]) / (d[1] - d[0]), Bu, Du, DDu);
  bernstein((v - d[2]) / (d[3] - d[2]), Bv, Dv, DDv);
  real3 P = splat_real3(0);
  for (int i = 0; i < 4; ++i)
  {
    real3 q0 = splat_real3(0);
    for (int j = 0; j < 4; ++j)
    {
      const int k = (4 * i + j) * 3;
      q0 += Bv[j] * make_real3(c[k], c[k + 1], c[k + 2]);
    }
    P += Bu[i] * q0;
  }
  return P;
}

PatchEval eval_patch(const Model* m, int p, real u, real v)
{
  __global const real* d = m->patchDomain + 4 * p;
  __global const real* c = m->patches + 48 * p;
  PatchEval e;
  real3 X, Y;
  if (plane_patch_frame(m, p, &X, &Y))
  {
    e.P = make_real3(c[0], c[1], c[2]) + (u - d[0]) * X + (v - d[2]) * Y;
    e.Du = X;
    e.Dv = Y;
    e.Duu = e.Duv = e.Dvv = splat_real3(0);
    return e;
  }
  const real du = d[1] - d[0], dv = d[3] - d[2];
  real Bu[4], Du[4], DDu[4], Bv[4], Dv[4], DDv[4];
  bernstein((u - d[0]) / du, Bu, Du, DDu);
  bernstein((v - d[2]) / dv, Bv, Dv, DDv);
  // Tensor product in two stages: the rows against the v basis, then the u basis.
  e.P = e.Du = e.Dv = e.Duu = e.Duv = e.Dvv = splat_real3(0);
  for (int i = 0; i < 4; ++i)
  {
    real3 q0 = splat_real3(0), q1 = splat_real3(0), q2 = splat_real3(0);
    for (int j = 0; j < 4; ++j)
    {
      const int k = (4 * i + j) * 3;
      const real3 q = make_real3(c[k], c[k + 1], c[k + 2]);
      q0 += Bv[j] * q;
      q1 += Dv[j] * q;
      q2 += DDv[j] * q;
    }
    e.P += Bu[i] * q0;
    e.Du += Du[i] * q0;
    e.Duu += DDu[i] * q0;
    e.Dv += Bu[i] * q1;
    e.Duv += Du[i] * q1;
    e.Dvv += Bu[i] * q2;
  }
  e.Du /= du;
  e.Dv /= dv;
  e.Duu /= du * du;
  e.Duv /= du * dv;
  e.Dvv /= dv * dv;
  return e;
}

// --- trimming curves ----------------------------------------------------------------------
inline real2 seg_point(__global const real* c, real t, real2* d1, real2* d2)
{
  real B[4], D[4], DD[4];
  bernstein(t, B, D, DD);
  real2 p = splat_real2(0), a = splat_real2(0), b = splat_real2(0);
  for (int i = 0; i < 4; ++i)
  {
    const real2 q = make_real2(c[2 * i], c[2 * i + 1]);
    p += B[i] * q;
    a += D[i] * q;
    b += DD[i] * q;
  }
  *d1 = a;
  *d2 = b;
  return p;
}

inline real seg_length(__global const real* c)
{
  return length(make_real2(c[2] - c[0], c[3] - c[1])) + length(make_real2(c[4] - c[2], c[5] - c[3])) +
    length(make_real2(c[6] - c[4], c[7] - c[5]));
}

// Control points within this (squared, relative to the chord's length) of a line's evenly spaced
// ones make a straight segment (project_segment).
#ifdef BRT_DOUBLE
#define LINEAR_SEGMENT_TOL2 ((real)1e-24)
#else
#define LINEAR_SEGMENT_TOL2 ((real)1e-12)
#endif

// Nearest point on a cubic 2D segment: eq. 6 from the polyline c(0), c(1/3), c(2/3), c(1).
real project_segment(__global const real* c, real2 P, real* dist)
{
  // A straight segment with evenly spaced control points (a line's, most of a planar face's
  // trim) is c0 + t (c3 - c0): its nearest point in closed form.
  {
    const real2 c0 = make_real2(c[0], c[1]), a = make_real2(c[6], c[7]) - c0;
    const real2 e1 = make_real2(c[2], c[3]) - c0 - a / (real)3;
    const real2 e2 = make_real2(c[4], c[5]) - c0 - (real)2 * a / (real)3;
    const real len2 = dot(a, a);
    if (len2 > (real)0 && dot(e1, e1) + dot(e2, e2) <= LINEAR_SEGMENT_TOL2 * len2)
    {
      const real t = clamp(dot(P - c0, a) / len2, (real)0, (real)1);
      // (At an end, the end control point itself: corners' ties stay exact.)
      const real2 q = t == (real)1 ? make_real2(c[6], c[7]) : c0 + t * a;
      *dist = length(q - P);
      return t;
    }
  }
  real2 d1, d2, poly[4];
  // (The curve's ends are its end control points, exactly.)
  poly[0] = make_real2(c[0], c[1]);
  poly[1] = seg_point(c, (real)1 / (real)3, &d1, &d2);
  poly[2] = seg_point(c, (real)2 / (real)3, &d1, &d2);
  poly[3] = make_real2(c[6], c[7]);
  real bestT = 0, bestD2 = REAL_MAX;
  for (int i = 0; i < 3; ++i)
  {
    const real2 a = poly[i + 1] - poly[i];
    const real len2 = dot(a, a);
    real tau = len2 > (real)0 ? dot(P - poly[i], a) / len2 : (real)0;
    tau = clamp(tau, (real)0, (real)1);
    const real2 q = poly[i] + tau * a - P;
    const real dd = dot(q, q);
    if (dd < bestD2)
    {
      bestD2 = dd;
      bestT = ((real)i + tau) / (real)3;
    }
  }
  real t = bestT;
  for (int it = 0; it < 12; ++it)
  {
    const real2 p = seg_point(c, t, &d1, &d2);
    const real2 r = p - P;
    const real f = dot(r, d1);
    const real df = dot(d1, d1) + dot(r, d2);
    if (df <= (real)0)
      break;
    const real next = clamp(t - f / df, (real)0, (real)1);
    const real step = fabs(next - t);
    t = next;
    if (step < (real)1e-15)
      break;
  }
  // The best of the Newton's point and the two ends (in this order: ties keep the first).
  real best = length(seg_point(c, t, &d1, &d2) - P), bestParam = t;
  const real d0 = length(poly[0] - P), d3 = length(poly[3] - P);
  if (d0 < best)
  {
    best = d0;
    bestParam = 0;
  }
  if (d3 < best)
  {
    best = d3;
    bestParam = 1;
  }
  *dist = best;
  return bestParam;
}

inline real2 seg_tangent(__global const real* c, real t)
{
  real2 d1, d2;
  seg_point(c, t, &d1, &d2);
  const real scale = seg_length(c);
  if (length(d1) > (real)1e-12 * scale)
    return d1;
  if (t < (real)0.5)
  {
    for (int i = 1; i < 4; ++i)
    {
      const real2 a = make_real2(c[2 * i] - c[0], c[2 * i + 1] - c[1]);
      if (length(a) > (real)1e-12 * scale)
        return a;
    }
  }
  else
  {
    for (int i = 2; i >= 0; --i)
    {
      const real2 a = make_real2(c[6] - c[2 * i], c[7] - c[2 * i + 1]);
      if (length(a) > (real)1e-12 * scale)
        return a;
    }
  }
  return make_real2(c[6] - c[0], c[7] - c[1]);
}

// Squared distance from P to the box b (u0, v0, u1, v1).
inline real uv_box_gap2(__global const real* b, real2 P)
{
  const real du = P.x < b[0] ? b[0] - P.x : (P.x > b[2] ? P.x - b[2] : (real)0);
  const real dv = P.y < b[1] ? b[1] - P.y : (P.y > b[3] ? P.y - b[3] : (real)0);
  return du * du + dv * dv;
}

// Squared distance from P to the box of a segment's control points: a lower bound on the
// squared distance to the curve (convex hull property). The box is packed after the control
// points (TRIM_REALS).
inline real box_distance2(__global const real* c, real2 P)
{
  return uv_box_gap2(c + 8, P);
}

inline real cross2(real2 a, real2 b)
{
  return a.x * b.y - a.y * b.x;
}

// Two distances to the trim within this (relative) of each other are a tie to classify: the
// projections' rounding orders them (and the nearest-segment search keeps every segment whose box
// lies within it of the best distance).
#ifdef BRT_DOUBLE
#define TRIM_TIE ((real)1e-6)
#else
#define TRIM_TIE ((real)1e-5)
#endif

// The nearest segment so far and the one after it (classify).
typedef struct
{
  real d, t;
  int seg, loop;
  real d2, t2;
  int seg2;
} NearSegments;

// Segment s of loop l, projected, replaces the best so far where nearer (ties: lower index); the
// one it replaces, or s where it is not nearer, replaces the second where nearer than that.
inline void nearer_segment(const Model* m, int l, int s, real2 P, NearSegments* n)
{
  __global const real* c = m->trim + TRIM_REALS * s;
  if (!(seg_length(c) > (real)0))
    return;
  real dd;
  const real t = project_segment(c, P, &dd);
  if (dd < n->d || (dd == n->d && s < n->seg))
  {
    n->d2 = n->d;
    n->t2 = n->t;
    n->seg2 = n->seg;
    n->d = dd;
    n->seg = s;
    n->t = t;
    n->loop = l;
  }
  else if (dd < n->d2 || (dd == n->d2 && s < n->seg2))
  {
    n->d2 = dd;
    n->t2 = t;
    n->seg2 = s;
  }
}

// (The crossing parity's test, defined with the certification's point test below.)
int inside_by_crossings(const Model* m, int face, real u, real v);

// Point-in-face test on the cubic trimming segments (the same steps as the host's
// brt::ClassifyPoint, Readers/Core/TrimClassifier, the crossing parity at a cusp included).
//
// *clearOut: a lower bound on the squared distance from P to the face's trimming curves, from the
// control boxes of the segments projected (each box's gap is at most its curve's distance, and
// the segments not projected have boxes farther than the nearest found): no trimming curve
// crosses the disk of that radius about P, so every point of it lies on P's side of the trim
// (descend_on_face and consider_point skip their trim tests there).
BRT_SPLIT int classify_clear(const Model* m, int face, real2 P, int* segOut, real* paramOut,
  real* distOut, real* clearOut)
{
  real clear2 = REAL_MAX;
  __global const int* fi = m->faceInfo + FACE_INTS * face;
  NearSegments n;
  n.d = REAL_MAX;
  n.t = 0;
  n.seg = -1;
  n.loop = -1;
  n.d2 = REAL_MAX;
  n.t2 = 0;
  n.seg2 = -1;
  // Nearest segment, ties to the lowest index; a segment whose control box is farther than the
  // best distance so far is not projected (rounding must not drop a tie: the bound is a little
  // wider). A face with a tree walks it nearest box first; the others take the nearest box
  // first, then the rest in order. Either way the same segment comes out.
  int firstSeg = -1, firstLoop = -1;
  real firstBound = REAL_MAX;
  if (fi[9] >= 0)
  {
    int stack[32];
    int top = 0;
    stack[top++] = fi[9];
    while (top > 0)
    {
      const int node = stack[--top];
      const real bound = n.d * ((real)1 + TRIM_TIE);
      if (uv_box_gap2(m->trimNodeBox + 4 * node, P) > bound * bound)
        continue;
      __global const int* ni = m->trimNodeInfo + 3 * node;
      if (ni[1] > 0)
      {
        // A leaf's segments (up to TRIM_LEAF), nearest box first: the first projection bounds
        // the rest.
        real gap[TRIM_LEAF];
        int order[TRIM_LEAF];
        const int cnt = ni[1] < TRIM_LEAF ? ni[1] : TRIM_LEAF;
        for (int j = 0; j < cnt; ++j)
        {
          const real g = box_distance2(m->trim + TRIM_REALS * m->trimItems[2 * (ni[0] + j)], P);
          int at = j;
          for (; at > 0 && gap[at - 1] > g; --at)
          {
            gap[at] = gap[at - 1];
            order[at] = order[at - 1];
          }
          gap[at] = g;
          order[at] = j;
        }
        for (int j = 0; j < cnt; ++j)
        {
          const real b = n.d * ((real)1 + TRIM_TIE);
          if (gap[j] > b * b)
            break;
          clear2 = fmin(clear2, gap[j]);
          const int i = ni[0] + order[j];
          nearer_segment(m, m->trimItems[2 * i + 1], m->trimItems[2 * i], P, &n);
        }
        continue;
      }
      const int left = node + 1, right = ni[2];
      const int leftFirst = uv_box_gap2(m->trimNodeBox + 4 * left, P) <=
        uv_box_gap2(m->trimNodeBox + 4 * right, P);
      if (top + 2 > 32)
        continue; // never: the tree is balanced (depth 31 holds 2^31 leaves)
      stack[top++] = leftFirst ? right : left;
      stack[top++] = leftFirst ? left : right;
    }
  }
  else
  for (int l = fi[4]; l < fi[4] + fi[5]; ++l)
  {
    const int first = m->loops[2 * l], count = m->loops[2 * l + 1];
    for (int s = first; s < first + count; ++s)
    {
      const real b = box_distance2(m->trim + TRIM_REALS * s, P);
      if (b < firstBound)
      {
        firstBound = b;
        firstSeg = s;
        firstLoop = l;
      }
    }
  }
  if (firstSeg >= 0)
  {
    clear2 = firstBound;
    nearer_segment(m, firstLoop, firstSeg, P, &n);
  }
  for (int l = fi[4]; l < fi[4] + fi[5] && firstSeg >= 0; ++l)
  {
    const int first = m->loops[2 * l], count = m->loops[2 * l + 1];
    for (int s = first; s < first + count; ++s)
    {
      const real bound = n.d * ((real)1 + TRIM_TIE); // rounding must not drop a tie
      const real gap = box_distance2(m->trim + TRIM_REALS * s, P);
      if (s != firstSeg && !(gap > bound * bound))
      {
        clear2 = fmin(clear2, gap);
        nearer_segment(m, l, s, P, &n);
      }
    }
  }
  *segOut = n.seg;
  *paramOut = n.t;
  *distOut = n.d;
  *clearOut = clear2;
  if (n.seg < 0)
    return 0;
  // A face whose loops cross themselves or each other (a lobe that runs the wrong way round, a
  // hook at a corner): the nearer curve puts a point beside the lobe on the wrong side at any
  // distance, and the parity of the crossings decides farther from the trim than four times the
  // chords' error (docs/Solver.md, item 5, "Loops that cross themselves").
  {
    __global const real* fd = m->faceDomain + FACE_REALS * face;
    const real chords = fd[FACE_LOOPS_CROSS];
    if (chords >= (real)0 &&
      n.d > (real)4 * chords + (real)1e-9 * (fd[1] - fd[0] + fd[3] - fd[2]))
      return inside_by_crossings(m, face, P.x, P.y);
  }
  const int bestSeg = n.seg, bestLoop = n.loop;
  const real bestT = n.t;
  __global const real* c = m->trim + TRIM_REALS * bestSeg;
  real2 d1, d2;
  const real2 q = P - seg_point(c, bestT, &d1, &d2);
  const real endEps = (real)1e-9;
  // A sliver, a segment a thousandth of the point's distance long, says nothing of the side a
  // point so far off lies on, and a loop's gap, welded or bridged, or a pcurve's tail can leave
  // one that turns back: the Framework logo cover's face 11 has a bridge 3.7e-4 long at a corner
  // that points backwards, whose tangent put a point 0.67 away inside the face outside it (a
  // sphere then held that face 0.35 deep). The nearest point on a sliver is taken as a corner,
  // and a corner's sides are the segments next to it that are not slivers.
  const real sliver = (real)1e-3 * length(q);
  const int onSliver = !(seg_length(c) > sliver);
  if (bestT > endEps && bestT < (real)1 - endEps && !onSliver)
  {
    const int side = cross2(seg_tangent(c, bestT), q) > (real)0;
    // A second segment as near (within TRIM_TIE) that puts the point on the other side: the
    // point lies beside a part of the face, or of a hole, far thinner than its distance, whose
    // two sides' curves run together, and may cross (a sliver face's tip on the Ploopy headband,
    // its loop a figure of eight there: beside it the nearer edge, by 1e-9, said inside, and a
    // contact 0.27 mm outside the face gave 2t 0.547 against the exact 0.696). The parity of the
    // crossings decides.
    if (n.seg2 >= 0 && n.d2 <= n.d * ((real)1 + TRIM_TIE) && n.t2 > endEps &&
      n.t2 < (real)1 - endEps)
    {
      __global const real* c2 = m->trim + TRIM_REALS * n.seg2;
      const real2 q2 = P - seg_point(c2, n.t2, &d1, &d2);
      if (seg_length(c2) > sliver && (cross2(seg_tangent(c2, n.t2), q2) > (real)0) != side)
        return inside_by_crossings(m, face, P.x, P.y);
    }
    return side;
  }
  const int first = m->loops[2 * bestLoop], count = m->loops[2 * bestLoop + 1];
  // The nearest segment that is not a sliver from `s` along the loop in `dir` (s itself left
  // out); any with a length where all are slivers, s where none has one.
  int before = bestSeg, after = bestSeg;
  for (int side = 0; side < 2; ++side)
  {
    const int dir = side == 0 ? -1 : 1;
    int idx = bestSeg - first, found = -1, any = -1;
    for (int k = 0; k + 1 < count && found < 0; ++k)
    {
      idx = (idx + dir + count) % count;
      const real len = seg_length(m->trim + TRIM_REALS * (first + idx));
      if (len > (real)0 && any < 0)
        any = first + idx;
      if (len > sliver)
        found = first + idx;
    }
    const int pick = found >= 0 ? found : (any >= 0 ? any : bestSeg);
    if (side == 0)
      before = pick;
    else
      after = pick;
  }
  // The corner's incoming and outgoing segments.
  const int incoming = (onSliver || bestT <= endEps) ? before : bestSeg;
  const int outgoing = (onSliver || bestT > endEps) ? after : bestSeg;
  const real2 ta = seg_tangent(m->trim + TRIM_REALS * incoming, (real)1);
  const real2 tb = seg_tangent(m->trim + TRIM_REALS * outgoing, (real)0);
  const real sa = cross2(ta, q), sb = cross2(tb, q);
  if ((sa > (real)0) == (sb > (real)0))
    return sa > (real)0;
  // Tangents within a thousandth of a radian of each other or of opposite (a loop that turns
  // back on itself at a cusp, or a corner all but smooth): the corner's turn is rounding there,
  // so the parity of the crossings decides. At cusps the corner rule put feet outside a spike
  // inside the face, and spheres touched the face's plane beyond its trim: control_arm read 2t
  // 0.0002-2.5 against the exact 10 on 39 samples, MVE_100 1 against 6 on 78, two Ender-3 fans
  // 0.65 against 2.35 on 5 each (docs/Solver.md, Open items, "The corner rule at a cusp").
  // Likewise where the corner's sides are not next to each other on the loop: the slivers between
  // them turn the loop too, and the turn from one side to the other alone may take the wrong way
  // round. A spike's tip on the classic Ploopy trackball's secondary buttons (face 10): a fillet
  // ending 1.4e-3 rad short of the way back, then a sliver 1.6e-4 long, then the way back; the
  // loop turns left by 180.08 degrees there, the two sides alone say right by 179.92, and points
  // 5-10 away outside the face came out inside (37 spheres too small, 2t 0.027 against the
  // exact 2.0; docs/Solver.md, item 5).
  const int adjacent = first + (incoming - first + 1) % count == outgoing;
  if (!adjacent || fabs(cross2(ta, tb)) < (real)1e-3 * length(ta) * length(tb))
    return inside_by_crossings(m, face, P.x, P.y);
  return cross2(ta, tb) < (real)0; // corner rule
}

inline int classify(const Model* m, int face, real2 P, int* segOut, real* paramOut, real* distOut)
{
  real clear2;
  return classify_clear(m, face, P, segOut, paramOut, distOut, &clear2);
}

// --- linear algebra -------------------------------------------------------------------------
inline real det3(const real J[3][3])
{
  return J[0][0] * (J[1][1] * J[2][2] - J[1][2] * J[2][1]) -
    J[0][1] * (J[1][0] * J[2][2] - J[1][2] * J[2][0]) +
    J[0][2] * (J[1][0] * J[2][1] - J[1][1] * J[2][0]);
}

int solve3(const real J[3][3], const real r[3], real x[3])
{
  const real det = det3(J);
  real bound = 1;
  for (int j = 0; j < 3; ++j)
    bound *= sqrt(J[0][j] * J[0][j] + J[1][j] * J[1][j] + J[2][j] * J[2][j]);
#ifdef BRT_DOUBLE
  const real rel = (real)1e-14;
#else
  const real rel = (real)1e-6;
#endif
  if (!(fabs(det) > rel * bound) || !(bound > (real)0))
    return 0;
  for (int c = 0; c < 3; ++c)
  {
    real A[3][3];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        A[i][j] = j == c ? r[i] : J[i][j];
    x[c] = det3(A) / det;
  }
  return 1;
}

int damped3(const real J[3][3], const real r[3], real x[3])
{
  real A[3][3], b[3], trace = 0;
  for (int i = 0; i < 3; ++i)
  {
    b[i] = 0;
    for (int j = 0; j < 3; ++j)
    {
      A[i][j] = 0;
      for (int k = 0; k < 3; ++k)
        A[i][j] += J[k][i] * J[k][j];
    }
    for (int k = 0; k < 3; ++k)
      b[i] += J[k][i] * r[k];
    trace += A[i][i];
  }
  if (!(trace > (real)0))
    return 0;
  for (int i = 0; i < 3; ++i)
    A[i][i] += (real)1e-9 * trace;
  return solve3(A, b, x);
}

inline real residual3(const PatchEval* e, const real R[3])
{
  const real lu = length(e->Du), lv = length(e->Dv);
  const real a = lu > (real)0 ? R[0] / lu : (real)0, b = lv > (real)0 ? R[1] / lv : (real)0;
  return sqrt(a * a + b * b + R[2] * R[2]);
}

// Point, first and second derivative of segment s of an edge at the edge's parameter T, the
// point relative to the sample O (C - O).
inline void eval_edge_segment(const Model* m, int s, real T, real3 Ohi, real3 Olo, real3* C,
  real3* Ct, real3* Ctt)
{
  const real T0 = m->edgeSegRange[2 * s], span = m->edgeSegRange[2 * s + 1] - T0;
  real B[4], D[4], DD[4];
  bernstein((T - T0) / span, B, D, DD);
  __global const real* c = m->edgeSeg + 12 * s;
  real3 p = splat_real3(0), a = splat_real3(0), b = splat_real3(0);
  for (int i = 0; i < 4; ++i)
  {
    const real3 q = make_real3(c[3 * i], c[3 * i + 1], c[3 * i + 2]);
    p += B[i] * q;
    a += D[i] * q;
    b += DD[i] * q;
  }
  *C = anchor_minus(m->edgeAnchor + 6 * s, Ohi, Olo) + p;
  *Ct = a / span;
  *Ctt = b / (span * span);
}

// Point, first and second derivative of an edge at edge parameter T.
// C is returned relative to the sample O (C - O).
void eval_edge(const Model* m, int edge, real T, real3 Ohi, real3 Olo, real3* C, real3* Ct,
  real3* Ctt)
{
  const int first = m->edgeInfo[4 * edge], count = m->edgeInfo[4 * edge + 1];
  // The first segment whose range ends at or after T (the last where none does): the segments
  // follow each other along T, so their ends rise and a bisection finds it.
  int s = first, last = first + count - 1;
  while (s < last)
  {
    const int mid = (s + last) / 2;
    if (T > m->edgeSegRange[2 * mid + 1])
      s = mid + 1;
    else
      last = mid;
  }
  eval_edge_segment(m, s, T, Ohi, Olo, C, Ct, Ctt);
}

// eval_edge at a T in or next to segment es's range: the segment eval_edge's bisection would
// find, stepped to from es (the first whose range ends at or after T; the ends rise).
inline void eval_edge_near(const Model* m, int edge, int es, real T, real3 Ohi, real3 Olo,
  real3* C, real3* Ct, real3* Ctt)
{
  const int first = m->edgeInfo[4 * edge], last = first + m->edgeInfo[4 * edge + 1] - 1;
  int s = es;
  while (s < last && T > m->edgeSegRange[2 * s + 1])
    ++s;
  while (s > first && !(T > m->edgeSegRange[2 * s - 1]))
    --s;
  eval_edge_segment(m, s, T, Ohi, Olo, C, Ct, Ctt);
}

// --- surface/surface Newton (eq. 4) ------------------------------------------------------
typedef struct
{
  real u, v, t, res, param, trimDist;
  int patch, singular, clamped, capped, inside, seg;
  real side; // (M - P).n_out at the foot point: <= 0 on the material side (from_inside)
  real3 normal; // the patch normal at the foot (not unit)
  real3 foot; // S - O
} SurfaceSolve;

inline int ss_converged(const SurfaceSolve* s, real newtonTol)
{
  // A run that hit the iteration cap with |R| just under the tolerance is not trusted.
  return s->res <= newtonTol && (!s->capped || s->res <= (real)1e-2 * newtonTol);
}

inline int ss_on_face(const SurfaceSolve* s, __global const real* fd, real newtonTol)
{
  return (s->inside || s->trimDist <= fd[6]) && (!s->clamped || ss_converged(s, newtonTol));
}

// Steps in a row without halving the residual that end a Newton (surface_newton).
#define STALL_STEPS 4

// The chain's memo answers the trim test at (u, v) on `face` (an isometric plane) where one of
// its disks holds (u, v) with room to spare: inside, the distance from the trim at least the
// room left (a lower bound of classify's exact distance), and no nearest segment kept (seg -1).
// The room asked for is the second look's radius (second_look_near: rho = max(1e-2 t, 10 slack))
// plus the larger of rho and the face's measured distance between its edges and their trimming
// segments' images (FACE_TRIM_EDGE_GAP), so that the second look, which takes the nearest
// segment's edge point where it lies within rho of the foot, would find none there either: on an
// isometric plane a distance in (u, v) is one in space, and the edge point lies within that gap
// of its segment's image.
inline int memo_inside(const Model* m, int face, real u, real v, real t, SurfaceSolve* out)
{
  ChainMemo* memo = m->memo;
  real3 X, Y;
  if (!memo || !plane_face_frame(m, face, &X, &Y))
    return 0;
  const real rho = fmax((real)1e-2 * t, (real)10 * m->slack);
  for (int k = 0; k < MEMO_DISKS; ++k)
  {
    if (memo->face[k] != face)
      continue;
    const real room = rho + fmax(rho, memo->gap[k]);
    const real du = u - memo->u[k], dv = v - memo->v[k];
    const real left = memo->r[k] - sqrt(du * du + dv * dv);
    if (!(left > room))
      return 0;
    out->inside = 1;
    out->seg = -1;
    out->param = (real)0;
    out->trimDist = left;
    return 1;
  }
  return 0;
}

// A trim test's answer on an isometric plane, inside at distance dist from the trim, becomes the
// chain's disk on that face (memo_inside), where its nearest point lies inside a segment that is
// not a sliver (param, on seg): there the side is the tangent's, along the normal from the
// curve, while at a corner the corner rule decides from the tangents, which fails next to a cusp
// (a loop that turns back on itself: control_arm's face 102, whose foot classify took for inside
// though it lies outside the spike; a disk around it spread that to the feet next to it).
inline void memo_record(const Model* m, int face, real u, real v, int inside, int seg,
  real param, real dist)
{
  ChainMemo* memo = m->memo;
  real3 X, Y;
  if (!memo || !inside || seg < 0 || !(param > (real)1e-9 && param < (real)(1.0 - 1e-9)) ||
    !(seg_length(m->trim + TRIM_REALS * seg) > (real)1e-3 * dist) ||
    !plane_face_frame(m, face, &X, &Y))
    return;
  int k = 0;
  while (k < MEMO_DISKS && memo->face[k] != face)
    ++k;
  if (k == MEMO_DISKS)
  {
    k = memo->next;
    memo->next = (memo->next + 1) % MEMO_DISKS;
  }
  memo->face[k] = face;
  memo->u[k] = u;
  memo->v[k] = v;
  memo->r[k] = (real)0.999 * dist;
  memo->gap[k] = m->faceDomain[FACE_REALS * face + FACE_TRIM_EDGE_GAP];
}

// Newton on (u, v, t) on `face`, with trust region and backtracking, then the trim test.
BRT_SPLIT SurfaceSolve surface_newton(const Model* m, int face, real3 Ohi, real3 Olo, real3 d, real u,
  real v, real t, real scale, real stepTol, real newtonTol, int maxIterations, int* iterations)
{
  __global const real* fd = m->faceDomain + FACE_REALS * face;
  SurfaceSolve out;
  out.singular = 0;
  int patch = find_patch(m, face, u, v);
  PatchEval e = eval_patch(m, patch, u, v);
  e.P += anchor_minus(m->patchAnchor + 6 * patch, Ohi, Olo); // now S - O
  real3 w = e.P - t * d;
  real R[3] = { dot(e.Du, w), dot(e.Dv, w), t - m->delta - length(w) }; // eq. 4, clearance
  real res = residual3(&e, R);
  int clamped = 0, capped = 1, slow = 0;
  for (int it = 0; it < maxIterations; ++it)
  {
    ++*iterations;
    const real L = length(w);
    if (L <= (real)0 || res < (real)1e-2 * stepTol)
    {
      capped = 0;
      break;
    }
    const real J[3][3] = { { dot(e.Du, e.Du) + dot(e.Duu, w), dot(e.Du, e.Dv) + dot(e.Duv, w), -dot(e.Du, d) },
      { dot(e.Dv, e.Du) + dot(e.Duv, w), dot(e.Dv, e.Dv) + dot(e.Dvv, w), -dot(e.Dv, d) },
      { -dot(w, e.Du) / L, -dot(w, e.Dv) / L, (real)1 + dot(w, d) / L } };
    const real mr[3] = { -R[0], -R[1], -R[2] };
    real x[3];
    if (!solve3(J, mr, x) && !damped3(J, mr, x))
    {
      out.singular = 1;
      capped = 0;
      break;
    }
    const real move = length(x[0] * e.Du + x[1] * e.Dv);
    const real limit = fmax((real)2 * fabs(t), (real)1e-2 * scale);
    real f = 1;
    if (move > limit)
      f = limit / move;
    if (fabs(x[2]) * f > limit)
      f = limit / fabs(x[2]);
    const real u0 = u, v0 = v, t0 = t, res0 = res;
    const PatchEval e0 = e;
    const int patch0 = patch, clamped0 = clamped;
    for (int k = 0; k <= 6; ++k, f *= (real)0.5)
    {
      real un = u0 + f * x[0], vn = v0 + f * x[1];
      if (fd[4] > (real)0) // across a seam of a closed face the parameter wraps
        un = fd[0] + (un - fd[0]) - fd[4] * floor((un - fd[0]) / fd[4]);
      if (fd[5] > (real)0)
        vn = fd[2] + (vn - fd[2]) - fd[5] * floor((vn - fd[2]) / fd[5]);
      u = clamp(un, fd[0], fd[1]);
      v = clamp(vn, fd[2], fd[3]);
      clamped = u != un || v != vn;
      t = t0 + f * x[2];
      patch = find_patch(m, face, u, v);
      e = eval_patch(m, patch, u, v);
      e.P += anchor_minus(m->patchAnchor + 6 * patch, Ohi, Olo);
      w = e.P - t * d;
      R[0] = dot(e.Du, w);
      R[1] = dot(e.Dv, w);
      R[2] = t - m->delta - length(w);
      res = residual3(&e, R);
      if (res < res0)
        break;
    }
    // No step along Newton's direction, down to 1/64 of it, lowers a residual above the
    // tolerance: there is no descent from here (a foot pushed against the domain's border, a
    // start on a face the sphere does not touch). Stop where it was, as capped, without the stall
    // rule's further rounds of seven evaluations each (three quarters of NIST_MBE_PMI_11's plane
    // samples ran one such Newton on a round next to their contact edge: 28 evaluations of 66).
    // Within the tolerance the residual is at its rounding in float, where no step need lower it,
    // and the stall rule decides as before (stopped there too, the float kernels left 0.05% more
    // samples to the double finish and ran at half their speed).
    if (!(res < res0) && res0 > newtonTol)
    {
      u = u0;
      v = v0;
      t = t0;
      res = res0;
      e = e0;
      patch = patch0;
      clamped = clamped0;
      w = e.P - t * d;
      break;
    }
    if (move + fabs(x[2]) < stepTol && !clamped && res <= newtonTol)
    {
      capped = 0;
      break;
    }
    // Stagnation: near a regular solution Newton's residual falls quadratically. One that has
    // not halved in STALL_STEPS steps in a row has no regular solution to go to (a whole arc of
    // contacts on a round, a foot held at the domain's border): stop as capped, as the
    // iteration cap would, without its evaluations.
    slow = res > (real)0.5 * res0 ? slow + 1 : 0;
    if (slow >= STALL_STEPS)
      break;
  }
  out.u = u;
  out.v = v;
  out.t = t;
  out.res = res;
  out.patch = patch;
  out.foot = e.P;
  out.clamped = clamped;
  out.capped = capped;
  if (!memo_inside(m, face, u, v, t, &out))
  {
    out.inside = classify(m, face, make_real2(u, v), &out.seg, &out.param, &out.trimDist);
    memo_record(m, face, u, v, out.inside, out.seg, out.param, out.trimDist);
  }
  const real3 n = cross(e.Du, e.Dv);
  const real side = -dot(w, n) / length(n) * (m->faceInfo[FACE_INTS * face + 6] ? -1 : 1);
  out.side = side;
  out.normal = n;
  return out;
}

// (u, v) on `face` of the point at edge parameter T of `edge`, from that face's trimming
// segments on the edge, with the unit direction (nu, nv) in (u, v) pointing from the edge into
// the face (0 where the segment's tangent vanishes); 0 if none covers T.
int edge_point_into_face(const Model* m, int face, int edge, real T, real* u, real* v, real* nu,
  real* nv)
{
  __global const int* fi = m->faceInfo + FACE_INTS * face;
  for (int l = fi[4]; l < fi[4] + fi[5]; ++l)
  {
    const int first = m->loops[2 * l], count = m->loops[2 * l + 1];
    for (int s = first; s < first + count; ++s)
    {
      if (m->trimEdge[s] != edge)
        continue; // (the edge first: the face's other segments skipped without their ranges)
      const real T0 = m->trimRange[2 * s], T1 = m->trimRange[2 * s + 1];
      const real lo = fmin(T0, T1), hi = fmax(T0, T1);
      if (T < lo || T > hi || hi <= lo)
        continue;
      real2 d1, d2;
      const real2 p = seg_point(m->trim + TRIM_REALS * s, (T - T0) / (T1 - T0), &d1, &d2);
      const real len = length(d1);
      *u = p.x;
      *v = p.y;
      *nu = len > (real)0 ? -d1.y / len : (real)0;
      *nv = len > (real)0 ? d1.x / len : (real)0;
      return 1;
    }
  }
  return 0;
}

inline int edge_point_on_face(const Model* m, int face, int edge, real T, real* u, real* v)
{
  real nu, nv;
  return edge_point_into_face(m, face, edge, T, u, v, &nu, &nv);
}

// --- the kernel -----------------------------------------------------------------------------
// The face of s1 point i: edge points (brt::S1Point::OnEdge) are stored as ~face.
inline int s1_face(__global const int* s1Face, int i)
{
  const int f = s1Face[i];
  return f < 0 ? ~f : f;
}

// Eq. 1's starts (initialise's s1 points, a chain's hint_start): *minDist, below which a point is
// O itself within rounding (the reference's 1e-9 of the model's size in double; float rounding
// needs more room), and *noise, how far a point must stand in front of O's tangent plane (0 in
// double; in float P - O carries rounding of about 1e-7 of the model's size, so a point of O's
// own face must stand clearly in front of it to count).
inline void start_tolerances(real scale, real* minDist, real* noise)
{
#ifdef BRT_DOUBLE
  *minDist = (real)1e-9 * scale;
  *noise = (real)0;
#else
  *minDist = (real)1e-5 * scale;
  *noise = (real)4 * FLT_EPSILON * scale;
#endif
}

// A point w = P - O can start eq. 1: e = d.w - delta exceeds max(1e-6 |w|, noise) (squared,
// without a root; l2 = |w|^2) and |w| exceeds minDist.
inline int starts_eq1(real e, real l2, real noise, real minDist)
{
  // One test, not three branches (initialise's point loop: the branches mispredicted).
  return (e > noise) & !(e * e <= (real)1e-12 * l2) & !(l2 <= minDist * minDist);
}

// Eq. 1 with the clearance over the BVH: the s1 point with the smallest
// t_delta below `bound` (REAL_MAX: any), pruning nodes farther than t - delta from M. With a
// finite bound it finds the s1 points more than delta deep inside that sphere (the verification);
// edgesOnly: only the points along the edges.
int initialise(__global const real* s1Point, __global const int* s1Face,
  __global const int* faceInfo, __global const real* nodeBox, __global const int* nodeInfo,
  real3 O, real3 d, int solid, int excludeFace, real scale, real bound, real delta, int edgesOnly,
  real* tOut)
{
  int best = -1;
  real t = bound;
  const int bounded = bound < REAL_MAX;
    real minDist, noise;
    start_tolerances(scale, &minDist, &noise);
    // A parent pushes only children its ball reaches, so an entry pushed since t last shrank
    // need not be tested against the ball again. The entries below staleBelow were pushed
    // before (the stack's order: a change makes every entry on it stale, and a pop below the
    // mark lowers it, since what is pushed next is pushed after the change); the root is
    // tested.
    int stack[64];
    int top = 0, staleBelow = 1;
    // The ball's centre and squared reach, kept with t (recomputed where a point shrinks it, not
    // per node).
    int ball = best >= 0 || bounded;
    real3 M = ball ? O + t * d : O;
    real reach2 = ball ? (t - delta) * (t - delta) : REAL_MAX;
    // Below a split root (brt::S1SplitRoot) the faces' points lie left, the edges' right: a start
    // (no bound) needs only the faces', the verification next to the certification only the
    // edges'.
    if (nodeInfo[0] == S1_SPLIT_ROOT && (!bounded || edgesOnly))
      stack[top] = bounded ? nodeInfo[2] : 1;
    else
      stack[top] = 0;
    ++top;
    while (top > 0)
    {
      --top;
      const int n = stack[top];
      const int fresh = top >= staleBelow;
      if (top < staleBelow)
        staleBelow = top;
      __global const real* bx = nodeBox + 6 * n;
      const real3 lo = make_real3(bx[0], bx[1], bx[2]), hi = make_real3(bx[3], bx[4], bx[5]);
      // A node wholly behind O's tangent plane holds no candidate: each of its points would be
      // skipped below (no point stands more than delta + max(1e-6 |P - O|, noise) in front of O,
      // and |P - O| is at least the node's distance from O). Without this a sample that no wall
      // faces (an exterior gap to infinity) visits every s1 point. A bounded walk needs no such
      // test: its ball lies in front of that plane, and the points are tested one by one anyway.
      if (!bounded)
      {
        const real3 ahead = make_real3(d.x > 0 ? hi.x : lo.x, d.y > 0 ? hi.y : lo.y, d.z > 0 ? hi.z : lo.z);
        const real3 gapToBox = max(max(lo - O, splat_real3(0)), O - hi);
        const real lead = dot(d, ahead - O) - delta; // against max(1e-6 |gap|, noise), squared
        if (!(lead > noise) || lead * lead <= (real)1e-12 * dot(gapToBox, gapToBox))
          continue;
      }
      if (ball && !fresh)
      {
        const real3 e = max(max(lo - M, splat_real3(0)), M - hi);
        if (dot(e, e) >= reach2)
          continue;
      }
      const int first = nodeInfo[3 * n], cnt = nodeInfo[3 * n + 1];
      // An inner node whose subtree lies on one solid has cnt = -(solid + 1) (brt::BVHNode):
      // another solid's subtree holds no candidate.
      if (cnt < 0 && solid >= 0 && -cnt - 1 != solid)
        continue;
      // An inner node whose points all lie on one face has that face as First (brt::BVHNode):
      // the face left out leaves its subtree out.
      if (cnt <= 0 && first >= 0 && first == excludeFace)
        continue;
      if (cnt > 0)
      {
        // Walls of other solids don't count: a leaf's points lie on one solid (brt::BVHNode),
        // its first point's.
        if (!in_scope(faceInfo, s1_face(s1Face, first), solid))
          continue;
        for (int i = first; i < first + cnt; ++i)
        {
          // Nor does a face already tried. Edge points (stored as ~face) only verify: they start
          // nothing (brt::AddEdgePoints); edgesOnly verifies with them alone.
          const int f = s1Face[i];
          if ((f < 0 ? !bounded : edgesOnly) || (f < 0 ? ~f : f) == excludeFace)
            continue;
          const real3 w = make_real3(s1Point[3 * i], s1Point[3 * i + 1], s1Point[3 * i + 2]) - O;
          const real e = dot(d, w) - delta, l2 = dot(w, w);
          // starts_eq1, and t_delta = (l2 - delta^2) / (2 e) below t compared without a
          // division, in one test (as four branches they mispredicted: -1.1% of
          // NIST_MBE_PMI_11's time in the native wide build).
          const real num = (real)0.5 * (l2 - delta * delta);
          if (starts_eq1(e, l2, noise, minDist) & (num < t * e))
          {
            t = num / e;
            best = i;
            staleBelow = top;
            ball = 1;
            M = O + t * d;
            reach2 = (t - delta) * (t - delta);
          }
        }
        continue;
      }
      const int left = n + 1, right = nodeInfo[3 * n + 2];
      __global const real* lb = nodeBox + 6 * left;
      __global const real* rb = nodeBox + 6 * right;
      const real3 el = max(max(make_real3(lb[0], lb[1], lb[2]) - M, splat_real3(0)), M - make_real3(lb[3], lb[4], lb[5]));
      const real3 er = max(max(make_real3(rb[0], rb[1], rb[2]) - M, splat_real3(0)), M - make_real3(rb[3], rb[4], rb[5]));
      const real dl = dot(el, el), dr = dot(er, er);
      const int leftFirst = dl <= dr;
      if (top + 2 > 64)
        continue;
      // A child the ball already misses is not pushed (the ball only shrinks, inside itself).
      const real dFar = leftFirst ? dr : dl;
      if (dFar < reach2)
        stack[top++] = leftFirst ? right : left;
      if ((leftFirst ? dl : dr) < reach2)
        stack[top++] = leftFirst ? left : right;
    }
  *tOut = t;
  return best;
}

// The depth below which a point inside a sphere proves nothing (the verification's and the
// certification's): the patches' accuracy (slack) or the clearance, and in float also its
// rounding of the model's coordinates, 4 FLT_EPSILON of its size (as initialise's noise): on a
// 6.7 m assembly the exact surfaces' distances carry 5e-4 mm of it, so the contact faces' bounds
// could not clear the 2e-4 mm depth and every patch of them was searched. The float kernels'
// finish certifies again in double at the patches' depth.
inline real check_depth(const Model* m, real scale)
{
#ifdef BRT_DOUBLE
  (void)scale;
  return fmax(m->delta, m->slack);
#else
  return fmax(fmax(m->delta, m->slack), (real)4 * FLT_EPSILON * scale);
#endif
}

// The verification of a sphere of radius t against s1: an s1 point more than `depth` inside it
// (its index; -1 where none), *tOut the radius of eq. 1 through it. Where the certification
// checks the patches themselves (MODE_CERTIFY), only the points along the edges: the
// certification finds what the faces' points would, and the edge points, taken from the exact
// edge curves, still catch a corner's edge reaching into the sphere within a few tolerances of O,
// where the certification counts nothing (docs/Solver.md, "The verification").
inline int verify_s1(const Model* m, __global const real* s1Point, __global const int* s1Face,
  __global const real* nodeBox, __global const int* nodeInfo, real3 O, real3 d, int solid,
  real scale, real t, real depth, real* tOut)
{
  return initialise(s1Point, s1Face, m->faceInfo, nodeBox, nodeInfo, O, d, solid, -1, scale,
    t * (real)(1.0 - 1e-6), depth, (m->mode & MODE_CERTIFY) != 0, tOut);
}

typedef struct
{
  real t, res;
  real3 foot; // relative to O
  real2 param; // (u, v) on face for surface/surface, (T, 0) on edge for edge contacts
  int type, reason, face, patch, edge;
  // The trim test at (face, trimUV) where the surface Newton made it (its nearest segment and
  // the parameter on it; trimSeg -2: none kept): the second look takes it instead of testing
  // the same point again.
  int trimSeg;
  real trimParam;
  real2 trimUV;
  int trimInside; // that test's answer
  real trimDist;  // and the distance from trimUV to the nearest trimming segment (UV)
  // Set where the shrinking ball refused a contact it touched from outside (shrink_ball): a
  // sample that fails after it fails as leaving the model, not as not maximal.
  int touchedOutside;
} Result;

// T within 1e-9 of the edge's parameter range of one of its ends: that vertex
//.
inline int at_edge_end(const Model* m, int edge, real T)
{
  const real T0 = m->edgeRange[4 * edge], T1 = m->edgeRange[4 * edge + 1];
  const real near = (real)1e-9 * fabs(T1 - T0);
  return fabs(T - T0) <= near || fabs(T - T1) <= near;
}

// A surface/edge or surface/vertex contact where the faces meet tangentially is a tangent
// contact with them: reported as surface/surface on the first face whose normal at the foot is
// within 1e-3 rad of the sphere's. foot is relative to O.
void type_tangent_edge_contact(const Model* m, real T, real3 d, Result* r)
{
  if ((r->type != CONTACT_SURFACE_EDGE && r->type != CONTACT_SURFACE_VERTEX) || r->edge < 0)
    return;
  const real3 q = r->foot - r->t * d; // foot - M
  const real lq = length(q);
  for (int k = 0; k < 2 && lq > (real)0; ++k)
  {
    const int f = m->edgeInfo[4 * r->edge + 2 + k];
    real u, v;
    if (f < 0 || m->faceInfo[FACE_INTS * f + 1] == 0 || !edge_point_on_face(m, f, r->edge, T, &u, &v))
      continue;
    const int patch = find_patch(m, f, u, v);
    const PatchEval e = eval_patch(m, patch, u, v);
    const real3 n = cross(e.Du, e.Dv);
    const real ln = length(n);
    if (!(ln > (real)0))
      continue;
    if (length(cross(n, q)) <= (real)1e-3 * ln * lq)
    {
      if (tangent_at_sample(m, r->foot, n, d))
      {
        // That face continues O's tangent plane at a foot next to O: the trivial solution.
        r->type = CONTACT_FAILED;
        r->reason = FAIL_LEFT_MODEL;
        return;
      }
      r->type = CONTACT_SURFACE_SURFACE;
      r->face = f;
      r->patch = patch;
      r->edge = -1;
      r->param = make_real2(u, v);
      return;
    }
  }
}

// t_delta(P) = (|P-O|^2 - delta^2) / (2 (d.(P-O) - delta)) for the boundary point P, given
// w = P - O: the radius at which the sphere tangent at O holds P delta deep (delta = 0:
// eq. 1); REAL_MAX when P is not more than delta in front of O.
// Why a clearance: where the sphere touches a whole arc (an osculating sphere on a round, a
// spherical corner blend) t(P) is flat along the arc up to the patches' error e, which it
// amplifies by 1 / (1 - cos theta) (theta the angle at M between O and P): minimising t, double
// and float picked different noise minima, up to 2% apart. t_delta adds about
// delta / (1 - cos theta), which the patches' error (< delta / 2) cannot cancel, so its minimum
// is the arc point farthest from O, well defined in both precisions. Near O, t_delta is large
// (P within delta of O's tangent plane gives none): the trivial and osculating solutions next to
// O disappear. The reported radius is eq. 1's t(P) at the foot found: exact wherever the contact
// is a strict minimum of t (plates, tubes, shells), within delta^2 / (2 t) elsewhere.
inline real sphere_radius(real3 d, real3 w, real delta)
{
  const real b = dot(d, w) - delta;
  return b > (real)0 ? (real)0.5 * (dot(w, w) - delta * delta) / b : REAL_MAX;
}

// A failed result with no reason (yet).
inline Result no_result(void)
{
  Result r;
  r.t = 0;
  r.res = 0;
  r.foot = splat_real3(0);
  r.param = splat_real2(0);
  r.type = CONTACT_FAILED;
  r.reason = FAIL_NONE;
  r.face = -1;
  r.patch = -1;
  r.edge = -1;
  r.touchedOutside = 0;
  r.trimSeg = -2;
  r.trimParam = 0;
  r.trimUV = splat_real2(0);
  r.trimInside = 0;
  r.trimDist = 0;
  return r;
}

// A surface Newton's result is a valid contact: converged on the face,
// positive and below the model's size, from inside, no osculating contact near O.
int valid_surface_solve(const Model* m, int sampleFace, int face, const SurfaceSolve* sn, real3 d,
  real scale, real newtonTol)
{
  return !sn->singular && sn->t > (real)0 && sn->t < scale && ss_converged(sn, newtonTol) &&
    from_inside(m, sampleFace, face, sn->side) && !tangent_at_sample(m, sn->foot, sn->normal, d) &&
    !shallow_own_face_contact(m, sampleFace, face, sn->foot, d, sn->t) &&
    ss_on_face(sn, m->faceDomain + FACE_REALS * face, newtonTol);
}

// The trimming segment next to degenerated segment `seg` of `face` in its loop that belongs to
// an edge (edgeInfo slot 1 set), and in *param the end of it at the pole: the one before it (its
// end, 1) or else the one after it (its start, 0). -1 where neither does.
int pole_neighbour(const Model* m, int face, int seg, real* param)
{
  __global const int* fi = m->faceInfo + FACE_INTS * face;
  for (int l = fi[4]; l < fi[4] + fi[5]; ++l)
  {
    const int first = m->loops[2 * l], count = m->loops[2 * l + 1];
    if (seg < first || seg >= first + count)
      continue;
    const int prev = seg == first ? first + count - 1 : seg - 1;
    const int next = seg == first + count - 1 ? first : seg + 1;
    if (m->trimEdge[prev] >= 0 && m->edgeInfo[4 * m->trimEdge[prev] + 1] != 0)
    {
      *param = (real)1;
      return prev;
    }
    if (m->trimEdge[next] >= 0 && m->edgeInfo[4 * m->trimEdge[next] + 1] != 0)
    {
      *param = (real)0;
      return next;
    }
    return -1;
  }
  return -1;
}

// Steps 4-7 (surface Newton, trim test, edge Newton, the face across the edge) from (face, u0,
// v0) with the initial radius t.
BRT_SPLIT Result solve_from(const Model* m, int sampleFace, real3 Ohi, real3 Olo, real3 d, int face, real u0, real v0,
  real t, real scale, real stepTol, real newtonTol, int maxIterations, int maxEdgeIterations,
  int* iterations)
{
  __global const real* faceDomain = m->faceDomain;
  __global const int* faceInfo = m->faceInfo;
  __global const int* edgeInfo = m->edgeInfo;
  __global const int* trimEdge = m->trimEdge;
  __global const real* trimRange = m->trimRange;
  __global const real* edgeRange = m->edgeRange;
  int type = CONTACT_FAILED, reason = FAIL_NONE, oppFace = -1, oppPatch = -1, oppEdge = -1;
  int trimSeg = -2, trimInside = 0;
  real trimParam = 0, trimDist = 0;
  real edgeT = 0;
  real res = 0;
  real3 foot = splat_real3(0);
  real2 footParam = splat_real2(0);
  // --- surface/surface Newton (eq. 4) with trust region and backtracking -------------------
  {
    __global const real* fd = faceDomain + FACE_REALS * face;
    const SurfaceSolve ss = surface_newton(m, face, Ohi, Olo, d, u0, v0, t, scale, stepTol,
      newtonTol, maxIterations, iterations);
    t = ss.t;
    res = ss.res;
    oppFace = face;
    if (ss.singular)
    {
      reason = FAIL_SINGULAR;
      goto out;
    }
    if (!(t > (real)0) || !(t < scale)) // no inscribed sphere is larger than the model
    {
      reason = FAIL_LEFT_MODEL;
      goto out;
    }
    if (ss_on_face(&ss, fd, newtonTol))
    {
      if (!ss_converged(&ss, newtonTol))
      {
        reason = FAIL_NOT_CONVERGED;
        goto out;
      }
      if (!from_inside(m, sampleFace, face, ss.side) ||
        tangent_at_sample(m, ss.foot, ss.normal, d) ||
        shallow_own_face_contact(m, sampleFace, face, ss.foot, d, ss.t))
      {
        reason = FAIL_LEFT_MODEL;
        goto out;
      }
      type = CONTACT_SURFACE_SURFACE;
      oppPatch = ss.patch;
      foot = ss.foot;
      footParam = make_real2(ss.u, ss.v);
      trimSeg = ss.seg;
      trimParam = ss.param;
      trimInside = ss.inside;
      trimDist = ss.trimDist;
      goto out;
    }
    int seg = ss.seg;
    real param = ss.param;
    // A degenerated trimming segment (a pole: its whole length is one point) stands for the
    // vertex it collapses to: eq. 7 starts there on the edge before it (or after it). Failing
    // there flagged the corners of a Phillips recess's floor, where its walls' B-spline faces
    // close in poles (Creality's Ender-3 pan-head screws, 3 samples each).
    if (seg >= 0 && trimEdge[seg] < 0)
      seg = pole_neighbour(m, face, seg, &param);

    // --- surface/edge Newton (eq. 7) --------------------------------------------------------
    if (seg < 0 || trimEdge[seg] < 0 || edgeInfo[4 * trimEdge[seg] + 1] == 0)
    {
      reason = FAIL_NO_EDGE;
      goto out;
    }
    const int edge = trimEdge[seg];
    real T = trimRange[2 * seg] + param * (trimRange[2 * seg + 1] - trimRange[2 * seg]);
    const real Tlo = fmin(edgeRange[4 * edge], edgeRange[4 * edge + 1]);
    const real Thi = fmax(edgeRange[4 * edge], edgeRange[4 * edge + 1]);
    int atEnd = 0, edgeCapped = 1;
    real3 C = splat_real3(0), Ct = splat_real3(0), Ctt = splat_real3(0);
    for (int it = 0; it < maxEdgeIterations; ++it)
    {
      eval_edge(m, edge, T, Ohi, Olo, &C, &Ct, &Ctt);
      const real3 we = C - t * d;
      const real L = length(we);
      const real lt = length(Ct);
      const real R0 = dot(Ct, we), R1 = t - m->delta - L; // eq. 7 with the clearance
      res = sqrt((lt > (real)0 ? (R0 / lt) * (R0 / lt) : (real)0) + R1 * R1);
      ++*iterations;
      if (L <= (real)0)
        break;
      const real J00 = dot(Ct, Ct) + dot(Ctt, we), J01 = -dot(Ct, d);
      const real J10 = -dot(we, Ct) / L, J11 = (real)1 + dot(we, d) / L;
      const real det = J00 * J11 - J01 * J10;
      if (!(fabs(det) > (real)0))
      {
        reason = FAIL_SINGULAR;
        goto out;
      }
      const real dT = (-R0 * J11 + R1 * J01) / det;
      const real dt = (-R1 * J00 + R0 * J10) / det;
      const real limit = fmax((real)2 * fabs(t), (real)1e-2 * scale);
      real f = 1;
      if (fabs(dT) * lt > limit)
        f = limit / (fabs(dT) * lt);
      if (fabs(dt) * f > limit)
        f = limit / fabs(dt);
      T += f * dT;
      t += f * dt;
      const real Tc = clamp(T, Tlo, Thi);
      if (Tc != T)
      {
        T = Tc;
        eval_edge(m, edge, T, Ohi, Olo, &C, &Ct, &Ctt);
        t = sphere_radius(d, C, m->delta);
        if (!(t < REAL_MAX))
        {
          reason = FAIL_LEFT_MODEL;
          goto out;
        }
        res = fabs(t - m->delta - length(C - t * d));
        atEnd = 1;
        edgeCapped = 0;
        break;
      }
      if (fabs(dT) * lt + fabs(dt) < stepTol && res <= newtonTol)
      {
        eval_edge(m, edge, T, Ohi, Olo, &C, &Ct, &Ctt);
        const real3 w2 = C - t * d;
        const real l2 = length(Ct);
        const real a = l2 > (real)0 ? dot(Ct, w2) / l2 : (real)0, b = t - m->delta - length(w2);
        res = sqrt(a * a + b * b);
        edgeCapped = 0;
        break;
      }
    }
    oppEdge = edge;
    const int edgeValid = t > (real)0 && t < scale;
    const int edgeConverged = res <= newtonTol && (!edgeCapped || res <= (real)1e-2 * newtonTol);
    // The face across that edge (see the reference): keep its sphere when it is valid and no
    // larger than the edge's, or when the edge Newton failed.
    {
      const int f0 = edgeInfo[4 * edge + 2], f1 = edgeInfo[4 * edge + 3];
      const int nb = f0 == face ? f1 : f0;
      real un, vn;
      if (nb >= 0 && nb != face && faceInfo[FACE_INTS * nb + 1] > 0 &&
        edge_point_on_face(m, nb, edge, T, &un, &vn))
      {
        const SurfaceSolve sn = surface_newton(m, nb, Ohi, Olo, d, un, vn, edgeValid ? t : ss.t,
          scale, stepTol, newtonTol, maxIterations, iterations);
        if (valid_surface_solve(m, sampleFace, nb, &sn, d, scale, newtonTol) &&
          (!(edgeValid && edgeConverged) || sn.t <= t * (real)(1.0 + 1e-12)))
        {
          type = CONTACT_SURFACE_SURFACE;
          reason = FAIL_NONE;
          oppFace = nb;
          oppPatch = sn.patch;
          oppEdge = -1;
          t = sn.t;
          res = sn.res;
          foot = sn.foot;
          footParam = make_real2(sn.u, sn.v);
          goto out;
        }
      }
    }
    if (!edgeValid) // no inscribed sphere is larger than the model
    {
      reason = FAIL_LEFT_MODEL;
      goto out;
    }
    if (!edgeConverged)
    {
      reason = FAIL_EDGE_NOT_CONVERGED;
      goto out;
    }
    if (edge_at_sample(m, sampleFace, edge, C))
    {
      reason = FAIL_LEFT_MODEL; // the trivial solution C = O
      goto out;
    }
    type = atEnd || at_edge_end(m, edge, T) ? CONTACT_SURFACE_VERTEX : CONTACT_SURFACE_EDGE;
    foot = C;
    edgeT = T;
    footParam = make_real2(T, 0);
  }

out:;
  Result r;
  r.t = t;
  r.res = res;
  r.foot = foot;
  r.param = footParam;
  r.type = type;
  r.reason = reason;
  r.face = oppFace;
  r.patch = oppPatch;
  r.edge = oppEdge;
  r.trimSeg = trimSeg;
  r.trimParam = trimParam;
  r.trimUV = footParam;
  r.trimInside = trimInside;
  r.trimDist = trimDist;
  r.touchedOutside = 0;
  type_tangent_edge_contact(m, edgeT, d, &r);
  return r;
}

// --- the descent fallback ------------------------------------------------------
// Steps shorter than this fraction of the model size end a descent (rounding).
#ifdef BRT_DOUBLE
#define DESCENT_TINY ((real)1e-14)
#else
#define DESCENT_TINY ((real)1e-7)
#endif

inline real wrap_param(real x, real lo, real period)
{
  return period > (real)0 ? lo + (x - lo) - period * floor((x - lo) / period) : x;
}

typedef struct
{
  real u, v, t;
  int patch;
  PatchEval e; // e.P relative to O
} DescentState;

inline void descent_eval(const Model* m, int face, real3 Ohi, real3 Olo, real3 d, real u, real v,
  DescentState* st)
{
  st->u = u;
  st->v = v;
  st->patch = find_patch(m, face, u, v);
  st->e = eval_patch(m, st->patch, u, v);
  st->e.P += anchor_minus(m->patchAnchor + 6 * st->patch, Ohi, Olo);
  st->t = sphere_radius(d, st->e.P, m->delta);
}

// Tangential part of eq. 4's residual at a state, as a distance: zero where t(u, v) is stationary.
inline real tangential_residual(const DescentState* st, real3 d)
{
  const real3 w = st->e.P - st->t * d;
  const real lu = length(st->e.Du), lv = length(st->e.Dv);
  const real a = lu > (real)0 ? dot(w, st->e.Du) / lu : (real)0;
  const real b = lv > (real)0 ? dot(w, st->e.Dv) / lv : (real)0;
  return sqrt(a * a + b * b);
}

// One face's part of the descent: minimises t(u, v) over the trimmed face
// from (u, v). A step is accepted when it lowers t by a sufficient amount, or, once t no longer
// changes beyond rounding (float near the minimum), when it lowers the tangential residual.
// *crossing: the trimming segment the last step wanted to cross (-1: a minimum inside).
BRT_SPLIT DescentState descend_on_face(const Model* m, int face, real3 Ohi, real3 Olo, real3 d, real u,
  real v, real scale, int maxIterations, int* crossing, int* iterations)
{
  __global const real* fd = m->faceDomain + FACE_REALS * face;
  const real tiny = DESCENT_TINY * scale;
  const real roundoff = (real)8 * REAL_EPS;
  DescentState cur;
  descent_eval(m, face, Ohi, Olo, d, u, v, &cur);
  *crossing = -1;
  if (!(cur.t < REAL_MAX))
    return cur;
  // The last point the trim test found inside, and the square of a radius about it that no
  // trimming curve enters (classify_clear, a thousandth of it kept as margin): the descent's
  // steps near its minimum end there, inside for certain, without a trim test.
  real knownU = 0, knownV = 0, knownR2 = (real)-1;
  real borderStep = 0; // the length of the step before where it crossed the trim, else 0
  int kinked = 0;
  DescentState before = cur; // the state before the last accepted step
  for (int it = 0; it < 4 * maxIterations; ++it)
  {
    ++*iterations;
    // grad t_delta = (S - M).S_u / (d.(S - O) - delta); the Hessian likewise.
    const real b = dot(d, cur.e.P) - m->delta, t = cur.t;
    const real3 w = cur.e.P - t * d; // S - M
    const real3 Su = cur.e.Du, Sv = cur.e.Dv;
    const real g0 = dot(w, Su) / b, g1 = dot(w, Sv) / b;
    const real dud = dot(d, Su), dvd = dot(d, Sv);
    const real H00 = (dot(Su, Su) - (real)2 * g0 * dud + dot(w, cur.e.Duu)) / b;
    const real H01 = (dot(Su, Sv) - g1 * dud - g0 * dvd + dot(w, cur.e.Duv)) / b;
    const real H11 = (dot(Sv, Sv) - (real)2 * g1 * dvd + dot(w, cur.e.Dvv)) / b;
    const real G00 = dot(Su, Su) / b, G01 = dot(Su, Sv) / b, G11 = dot(Sv, Sv) / b;
    // Levenberg-Marquardt: H + lambda G, lambda raised until positive definite.
    real s0 = 0, s1 = 0;
    for (real lambda = 0; lambda < (real)1e12;
         lambda = lambda == (real)0 ? (real)1e-3 : (real)10 * lambda)
    {
      const real a00 = H00 + lambda * G00, a01 = H01 + lambda * G01, a11 = H11 + lambda * G11;
      const real det = a00 * a11 - a01 * a01;
      if (a00 > (real)0 && det > (real)0)
      {
        s0 = -(a11 * g0 - a01 * g1) / det;
        s1 = -(a00 * g1 - a01 * g0) / det;
        break;
      }
    }
    const real len = length(s0 * Su + s1 * Sv);
    const real limit = fmax(t, (real)1e-3 * scale);
    real f = len > limit ? limit / len : (real)1;
    // Along the face's border (the step before was halved after one that left the face), the
    // line search starts at twice the step's length before rather than at the whole step: each
    // halving outside the face was a trim test, about a dozen per step along a border.
    if (borderStep > (real)0 && f * len > (real)2 * borderStep)
      f = (real)2 * borderStep / len;
    const real slope = g0 * s0 + g1 * s1;
    *crossing = -1;
    if (len * f < tiny || !(slope < (real)0))
      break; // stationary: a minimum of t on the face
    const real res0 = tangential_residual(&cur, d);
    const real stepUV = sqrt(s0 * s0 + s1 * s1);
    const real f0 = f; // the length the line search starts from (the kink test below)
    // Steps longer than this end outside the face for certain, without a trim test (below).
    real outsideAbove = REAL_MAX;
    int accepted = 0;
    for (int k = 0; k < 40; ++k, f *= (real)0.5)
    {
      const real un = wrap_param(cur.u + f * s0, fd[0], fd[4]);
      const real vn = wrap_param(cur.v + f * s1, fd[2], fd[5]);
      const real uc = clamp(un, fd[0], fd[1]), vc = clamp(vn, fd[2], fd[3]);
      const int outsideDomain = uc != un || vc != vn;
      // A step past the domain is halved again; the trim test only names the first crossing
      // (most steps of a descent along the domain's border end here, each a trim test before).
      if ((outsideDomain && *crossing >= 0) || f > outsideAbove)
        continue;
      int seg = -1, inside = 1;
      real param = 0, dist = 0, clear2;
      if (outsideDomain || !((uc - knownU) * (uc - knownU) + (vc - knownV) * (vc - knownV) < knownR2))
      {
        inside = classify_clear(m, face, make_real2(uc, vc), &seg, &param, &dist, &clear2);
        if (inside && !outsideDomain)
        {
          knownU = uc;
          knownV = vc;
          knownR2 = (real)0.998 * clear2;
        }
      }
      if (!(inside || dist <= fd[6]) || outsideDomain)
      {
        if (*crossing < 0)
          *crossing = seg; // the first (longest) step that left the face
        // A point outside the trim by dist - fd[6] has no trim within that distance: the steps
        // that end closer to it (a shorter step along the same line, without a wrap) are
        // outside too. Most halvings of a descent towards its face's border end outside; this
        // skips their trim tests (a thousandth of the distance kept as margin).
        if (!inside && !outsideDomain && un == cur.u + f * s0 && vn == cur.v + f * s1 &&
          stepUV > (real)0 && dist > fd[6])
          outsideAbove = f - (real)0.999 * (dist - fd[6]) / stepUV;
        continue;
      }
      DescentState next;
      descent_eval(m, face, Ohi, Olo, d, uc, vc, &next);
      if (next.t <= t + (real)1e-4 * f * slope ||
        (next.t <= t + roundoff * t && tangential_residual(&next, d) < res0))
      {
        before = cur;
        cur = next;
        accepted = 1;
        break;
      }
    }
    if (!accepted || len * f < tiny)
      break;
    borderStep = *crossing >= 0 ? f * len : (real)0;
    // A minimum on the join of two patches is a kink of t: a free-form face's patches join with
    // C0 continuity only (docs/Design.md, item 3), their tangent planes a little apart there. The
    // step from it crosses the join, and the line search halves it until it barely moves, for a
    // gain far below any tolerance; the descent crept so up to its cap of 4 x maxIterations steps.
    // Three steps in a row that were accepted at a 64th of the full step or less, moving less
    // than a thousandth of the slack, and whose step at the line search's first length crossed
    // into another patch (before, from `before`: a join crossed) end the descent there
    // (docs/Solver.md, item 9, "At a patch join": 2,400 descents of AnalysisSitus's 1 m storage
    // part ran to the cap before). The patch lookup only where the other two hold.
    const int creeping = f * len <= (real)1e-3 * m->slack && f < (real)0.015625;
    kinked = creeping &&
        find_patch(m, face, clamp(wrap_param(before.u + f0 * s0, fd[0], fd[4]), fd[0], fd[1]),
          clamp(wrap_param(before.v + f0 * s1, fd[2], fd[5]), fd[2], fd[3])) != before.patch
      ? kinked + 1
      : 0;
    if (kinked >= 3)
    {
      // The side of the join whose tangent plane leaves the smaller residual: the contact's
      // check (descend) takes the residual at the point it is given, and the two sides' differ by
      // the kink (6.1e-5 and 1.5e-4 on the classic trackball's wedge, whose descent alternated
      // between the two patches at t equal to 1e-11).
      if (res0 < tangential_residual(&cur, d))
        cur = before;
      break;
    }
  }
  return cur;
}

// The minimum of t_delta(C(T)) along `edge` from T: Newton on t'(T) where
// t(T) is convex, else the longest step downhill, with line search; stops at the edge's ends.
typedef struct
{
  real T, t;
  real3 C, Ct; // C relative to O
  int atEnd;
} EdgeMinimum;

EdgeMinimum minimise_on_edge(const Model* m, int edge, real T, real3 Ohi, real3 Olo, real3 d,
  real scale, int maxEdgeIterations, int* iterations)
{
  const real tiny = DESCENT_TINY * scale;
  const real roundoff = (real)8 * REAL_EPS;
  const real Tlo = fmin(m->edgeRange[4 * edge], m->edgeRange[4 * edge + 1]);
  const real Thi = fmax(m->edgeRange[4 * edge], m->edgeRange[4 * edge + 1]);
  T = clamp(T, Tlo, Thi);
  real3 C, Ct, Ctt;
  eval_edge(m, edge, T, Ohi, Olo, &C, &Ct, &Ctt);
  real t = sphere_radius(d, C, m->delta);
  int atEnd = T == Tlo || T == Thi; // (a start at an end that no step leaves is that vertex)
  for (int it = 0; it < 2 * maxEdgeIterations && t < REAL_MAX; ++it)
  {
    ++*iterations;
    const real b = dot(d, C) - m->delta;
    const real3 w = C - t * d;
    const real g = dot(w, Ct) / b;
    const real dCt = dot(d, Ct);
    const real h = (dot(Ct, Ct) - (real)2 * g * dCt + dot(w, Ctt)) / b;
    const real speed = length(Ct);
    const real limit = fmax(t, (real)1e-3 * scale);
    real dT = h > (real)0 ? -g / h : (g > (real)0 ? (real)-1 : (real)1) * limit / fmax(speed, REAL_MIN);
    if (fabs(dT) * speed > limit)
      dT *= limit / (fabs(dT) * speed);
    if (fabs(dT) * speed < tiny)
      break;
    const real res0 = speed > (real)0 ? fabs(dot(w, Ct)) / speed : (real)0;
    int accepted = 0;
    for (int k = 0; k < 40; ++k, dT *= (real)0.5)
    {
      const real Tn = clamp(T + dT, Tlo, Thi);
      real3 Cn, Ctn, Cttn;
      eval_edge(m, edge, Tn, Ohi, Olo, &Cn, &Ctn, &Cttn);
      const real tn = sphere_radius(d, Cn, m->delta);
      const real sn = length(Ctn);
      const real resn = sn > (real)0 ? fabs(dot(Cn - tn * d, Ctn)) / sn : (real)0;
      if (tn <= t + (real)1e-4 * g * (Tn - T) || (tn <= t + roundoff * t && resn < res0))
      {
        atEnd = Tn == Tlo || Tn == Thi;
        accepted = T != Tn;
        T = Tn;
        C = Cn;
        Ct = Ctn;
        Ctt = Cttn;
        t = tn;
        break;
      }
    }
    if (!accepted)
      break;
  }
  EdgeMinimum em;
  em.T = T;
  em.t = t;
  em.C = C;
  em.Ct = Ct;
  em.atEnd = atEnd;
  return em;
}

// The contact at an edge minimum on `face`'s edge: surface/edge, or
// surface/vertex at an end (typed surface/surface where the faces meet tangentially); failed
// where t is not positive or eq. 7's residual is above the tolerance.
Result edge_contact(const Model* m, int sampleFace, int face, int edge, const EdgeMinimum* em,
  real3 d, real newtonTol)
{
  Result r = no_result();
  const real t = em->t;
  const real3 w = em->C - t * d;
  const real lt = length(em->Ct);
  const real a = lt > (real)0 ? dot(em->Ct, w) / lt : (real)0, bb = t - m->delta - length(w);
  r.res = em->atEnd ? fabs(bb) : sqrt(a * a + bb * bb);
  if (!(t > (real)0) || !(t < REAL_MAX) || edge_at_sample(m, sampleFace, edge, em->C))
    r.reason = FAIL_LEFT_MODEL; // (or the trivial solution C = O)
  else if (!(r.res <= newtonTol))
    r.reason = FAIL_EDGE_NOT_CONVERGED;
  if (r.reason != FAIL_NONE)
    return r;
  r.type = em->atEnd || at_edge_end(m, edge, em->T) ? CONTACT_SURFACE_VERTEX
                                                    : CONTACT_SURFACE_EDGE;
  r.face = face;
  r.edge = edge;
  r.t = t;
  r.foot = em->C;
  r.param = make_real2(em->T, 0);
  type_tangent_edge_contact(m, em->T, d, &r);
  return r;
}

// The descent fallback: minimises t over the trimmed face from (u, v); where the
// minimum lies on the face's boundary, along the nearest edge, and from the edge's minimum into
// the face across it where t falls that way, up to 4 faces. Mirrors the reference step for step.
BRT_SPLIT Result descend(const Model* m, int sampleFace, int face, real3 Ohi, real3 Olo, real3 d, real u,
  real v, real scale, real newtonTol, int maxIterations, int maxEdgeIterations, int* iterations)
{
  Result best = no_result();
  for (int hop = 0; hop < 4; ++hop)
  {
    int crossing = -1;
    const DescentState cur =
      descend_on_face(m, face, Ohi, Olo, d, u, v, scale, maxIterations, &crossing, iterations);
    // The face's result: a minimum of t inside it (when no edge result is lower).
    Result fr = best;
    fr.type = CONTACT_FAILED;
    fr.reason = FAIL_NONE;
    if (cur.t < REAL_MAX)
    {
      const real3 w = cur.e.P - cur.t * d;
      const real R[3] = { dot(cur.e.Du, w), dot(cur.e.Dv, w), cur.t - m->delta - length(w) };
      const real reversed = m->faceInfo[FACE_INTS * face + 6] ? (real)-1 : (real)1;
      fr.res = residual3(&cur.e, R);
      const real3 n = cross(cur.e.Du, cur.e.Dv);
      if (!from_inside(m, sampleFace, face, -dot(w, n) / length(n) * reversed))
        fr.reason = FAIL_LEFT_MODEL; // touches the face from outside
      else if (at_sample(m, sampleFace, face, cur.e.P) || tangent_at_sample(m, cur.e.P, n, d))
        fr.reason = FAIL_LEFT_MODEL; // the trivial solution P = O
      else if (!(fr.res <= newtonTol) || !(cur.t > (real)0) || !(cur.t < scale))
        fr.reason = FAIL_NOT_CONVERGED;
      else
      {
        fr.type = CONTACT_SURFACE_SURFACE;
        fr.face = face;
        fr.patch = cur.patch;
        fr.edge = -1;
        fr.t = cur.t;
        fr.foot = cur.e.P;
        fr.param = make_real2(cur.u, cur.v);
      }
    }
    const int faceOk = fr.type != CONTACT_FAILED; // the face point itself is a tangent sphere
    if (best.type != CONTACT_FAILED && (fr.type == CONTACT_FAILED || !(fr.t < best.t)))
      fr = best;
    if (crossing < 0)
      return fr;
    // The edge: the trimming segment nearest the last point, else the crossed one.
    int nearSeg;
    real nearAt, nearDist;
    classify(m, face, make_real2(cur.u, cur.v), &nearSeg, &nearAt, &nearDist);
    int segment = crossing;
    real at;
    if (nearSeg >= 0 && m->trimEdge[nearSeg] >= 0)
    {
      segment = nearSeg;
      at = nearAt;
    }
    else
    {
      real dist;
      at = project_segment(m->trim + TRIM_REALS * crossing, make_real2(cur.u, cur.v), &dist);
    }
    const int edge = m->trimEdge[segment];
    if (edge < 0 || m->edgeInfo[4 * edge + 1] == 0)
      return fr; // a pole: stay at the best point of the face
    // Along the edge: minimise t(T).
    const real T0 = m->trimRange[2 * segment], T1 = m->trimRange[2 * segment + 1];
    const EdgeMinimum em = minimise_on_edge(m, edge, T0 + at * (T1 - T0), Ohi, Olo, d, scale,
      maxEdgeIterations, iterations);
    const real t = em.t;
    // Keep the face point (or the last edge contact) where it is lower; where the face point
    // is no tangent sphere (a round's tangent edge), the edge goes on even at the same t.
    if (!(t < (best.type == CONTACT_FAILED ? scale : best.t)) ||
      (faceOk && !(t < cur.t)))
      return fr;
    const Result r = edge_contact(m, sampleFace, face, edge, &em, d, newtonTol);
    if (r.type == CONTACT_FAILED)
      return best.type != CONTACT_FAILED ? best : r;
    best = r;
    // Across the edge, where t falls into the neighbour face (a round's tangent plane).
    const int f0 = m->edgeInfo[4 * edge + 2], f1 = m->edgeInfo[4 * edge + 3];
    const int nb = f0 == face ? f1 : f0;
    real un, vn, nu, nv;
    if (em.atEnd || nb < 0 || nb == face || m->faceInfo[FACE_INTS * nb + 1] == 0 ||
      !edge_point_into_face(m, nb, edge, em.T, &un, &vn, &nu, &nv))
      return best;
    const int pn = find_patch(m, nb, un, vn);
    PatchEval en = eval_patch(m, pn, un, vn);
    en.P += anchor_minus(m->patchAnchor + 6 * pn, Ohi, Olo);
    const real3 wn = en.P - t * d;
    if (!(dot(wn, en.Du) * nu + dot(wn, en.Dv) * nv < (real)0))
      return best;
    face = nb;
    u = un;
    v = vn;
  }
  return best;
}

// Descends on the face across the edge nearest O (O's projection on its own trim, from classify
// at ownUV): a sample next to a convex edge has a sphere of about its distance from the edge,
// closer to O than any s1 point. The start is moved into that face by the offset (1e-6 to 1e-1 of
// its UV diagonal) that gives the smallest t.
BRT_SPLIT Result descend_across_nearest_edge(const Model* m, int ownFace, real2 ownUV, real3 Ohi,
  real3 Olo, real3 d, real scale, real newtonTol, int maxIterations, int maxEdgeIterations,
  int* iterations)
{
  Result none = no_result();
  int ownSeg;
  real ownParam, ownDist;
  classify(m, ownFace, ownUV, &ownSeg, &ownParam, &ownDist);
  if (ownSeg < 0 || m->trimEdge[ownSeg] < 0)
    return none;
  const int edge = m->trimEdge[ownSeg];
  const int f0 = m->edgeInfo[4 * edge + 2], f1 = m->edgeInfo[4 * edge + 3];
  const int nb = f0 == ownFace ? f1 : f0;
  if (nb < 0 || nb == ownFace || m->faceInfo[FACE_INTS * nb + 1] == 0)
    return none;
  const real T = m->trimRange[2 * ownSeg] +
    ownParam * (m->trimRange[2 * ownSeg + 1] - m->trimRange[2 * ownSeg]);
  real u0, v0, nu, nv;
  if (!edge_point_into_face(m, nb, edge, T, &u0, &v0, &nu, &nv))
    return none;
  __global const real* fd = m->faceDomain + FACE_REALS * nb;
  const real diag = length(make_real2(fd[1] - fd[0], fd[3] - fd[2]));
  real bestT = REAL_MAX, bu = 0, bv = 0;
  for (real h = (real)1e-6; h < (real)0.2; h *= (real)10)
  {
    const real u = clamp(u0 + h * diag * nu, fd[0], fd[1]);
    const real v = clamp(v0 + h * diag * nv, fd[2], fd[3]);
    int sg;
    real pr, ds;
    if (!classify(m, nb, make_real2(u, v), &sg, &pr, &ds))
      continue;
    DescentState st;
    descent_eval(m, nb, Ohi, Olo, d, u, v, &st);
    if (st.t < bestT)
    {
      bestT = st.t;
      bu = u;
      bv = v;
    }
  }
  if (!(bestT < REAL_MAX))
    return none;
  return descend(m, ownFace, nb, Ohi, Olo, d, bu, bv, scale, newtonTol, maxIterations,
    maxEdgeIterations, iterations);
}

// The second look at a verified contact (docs/Solver.md): the minimum along the edge next to a
// surface contact (within rho); the surface Newton on the faces beside an edge contact; the
// edges and faces around a vertex next to the contact. Each is a Newton from the contact itself,
// a sphere tangent at O inside the verified one: the smallest wins. (The far end of an arc and
// the face across the edge nearest O, looked at before the certification against the patches,
// bought nothing measurable since and cost a third of the solve: docs/Solver.md.)
// The vertex at the end of `edge` nearer T, when within rho of `foot` (relative to O).
void near_vertex(const Model* m, int edge, real T, real3 foot, real rho, real3 Ohi, real3 Olo,
  int* vertexEdge, int* vertexEnd)
{
  const real T0 = m->edgeRange[4 * edge], T1 = m->edgeRange[4 * edge + 1];
  const int end = fabs(T - T1) < fabs(T - T0) ? 1 : 0;
  real3 C, Ct, Ctt;
  eval_edge(m, edge, end ? T1 : T0, Ohi, Olo, &C, &Ct, &Ctt);
  const real3 gap = C - foot;
  if (dot(gap, gap) <= rho * rho)
  {
    *vertexEdge = edge;
    *vertexEnd = end;
  }
}

// The surface/surface contact of a surface Newton's result on `face`.
inline Result surface_result(int face, const SurfaceSolve* ss)
{
  Result c = no_result();
  c.type = CONTACT_SURFACE_SURFACE;
  c.face = face;
  c.patch = ss->patch;
  c.t = ss->t;
  c.res = ss->res;
  c.foot = ss->foot;
  c.param = make_real2(ss->u, ss->v);
  return c;
}

// The edges and faces at the vertex at end `end` of `edge`, from a contact of radius t at or
// next to it: the minimum along each edge from the vertex and the surface Newton on each face
// from it (but skipFace) replace *r where lower.
BRT_SPLIT void around_vertex(const Model* m, int ownFace, int faceOfEdge, int edge, int end, int skipFace,
  real t, real3 Ohi, real3 Olo, real3 d, real scale, real stepTol, real newtonTol,
  int maxIterations, int maxEdgeIterations, int* iterations, Result* r)
{
  const real roundoff = REAL_EPS;
  const int record = m->vertexInfo[2 * edge + end];
  if (record < 0)
    return;
  int tried[8] = { skipFace, -1, -1, -1, -1, -1, -1, -1 };
  int triedCount = 1;
  const int n = m->vertexInfo[record];
  for (int i = 1; i <= n; ++i)
  {
    const int e = m->vertexInfo[record + i] / 2;
    const real Te = m->edgeRange[4 * e + m->vertexInfo[record + i] % 2];
    const EdgeMinimum em =
      minimise_on_edge(m, e, Te, Ohi, Olo, d, scale, maxEdgeIterations, iterations);
    Result c = edge_contact(
      m, ownFace, e == edge ? faceOfEdge : m->edgeInfo[4 * e + 2], e, &em, d, newtonTol);
    if (c.type != CONTACT_FAILED && c.t < r->t * ((real)1 - roundoff))
      *r = c;
    for (int k = 0; k < 2; ++k)
    {
      const int f = m->edgeInfo[4 * e + 2 + k];
      int seen = f < 0 || m->faceInfo[FACE_INTS * f + 1] == 0;
      for (int j = 0; j < triedCount && !seen; ++j)
        seen = tried[j] == f;
      if (seen)
        continue;
      if (triedCount < 8)
        tried[triedCount++] = f;
      real u, v;
      if (!edge_point_on_face(m, f, e, Te, &u, &v))
        continue;
      const SurfaceSolve ss = surface_newton(m, f, Ohi, Olo, d, u, v, t, scale, stepTol,
        newtonTol, maxIterations, iterations);
      if (valid_surface_solve(m, ownFace, f, &ss, d, scale, newtonTol) &&
        ss.t < r->t * ((real)1 - roundoff))
        *r = surface_result(f, &ss);
    }
  }
}

// The local part of the second look: the minimum along the edge next to
// a surface contact, the surface Newton on the faces beside an edge contact, and the edges and
// faces around the vertex at or next to the contact.
BRT_SPLIT void second_look_near(const Model* m, int ownFace, real3 Ohi, real3 Olo, real3 d, real scale,
  real stepTol, real newtonTol, int maxIterations, int maxEdgeIterations, int* iterations,
  Result* r)
{
  if (r->type == CONTACT_FAILED)
    return;
  const real rho = fmax((real)1e-2 * r->t, (real)10 * m->slack);
  const real roundoff = REAL_EPS;
  int vertexEdge = -1, vertexEnd = 0;
  const Result first = *r;
  Result c;
  if (r->type == CONTACT_SURFACE_SURFACE)
  {
    int seg;
    real param, dist;
    if (r->trimSeg != -2 && r->trimUV.x == r->param.x && r->trimUV.y == r->param.y)
    {
      seg = r->trimSeg;
      param = r->trimParam;
    }
    else
      classify(m, r->face, r->param, &seg, &param, &dist);
    if (seg >= 0 && m->trimEdge[seg] >= 0)
    {
      const int edge = m->trimEdge[seg];
      const real T =
        m->trimRange[2 * seg] + param * (m->trimRange[2 * seg + 1] - m->trimRange[2 * seg]);
      real3 C, Ct, Ctt;
      eval_edge(m, edge, T, Ohi, Olo, &C, &Ct, &Ctt);
      const real3 gap = C - r->foot;
      if (dot(gap, gap) <= rho * rho)
      {
        near_vertex(m, edge, T, r->foot, rho, Ohi, Olo, &vertexEdge, &vertexEnd);
        const EdgeMinimum em =
          minimise_on_edge(m, edge, T, Ohi, Olo, d, scale, maxEdgeIterations, iterations);
        c = edge_contact(m, ownFace, r->face, edge, &em, d, newtonTol);
        if (c.type != CONTACT_FAILED && c.t < r->t * ((real)1 - roundoff))
          *r = c;
      }
    }
  }
  if (r->type != CONTACT_SURFACE_SURFACE && r->edge >= 0)
  {
    const int edge = r->edge;
    const real T = r->param.x, t = r->t;
    near_vertex(m, edge, T, r->foot, rho, Ohi, Olo, &vertexEdge, &vertexEnd);
    // (From a vertex, around_vertex starts the same Newtons on these faces.)
    const int fromVertex = r->type == CONTACT_SURFACE_VERTEX;
    for (int k = 0; k < 2 && !fromVertex; ++k)
    {
      const int f = m->edgeInfo[4 * edge + 2 + k];
      real u, v, nu, nv;
      if (f < 0 || (k == 1 && f == m->edgeInfo[4 * edge + 2]) ||
        m->faceInfo[FACE_INTS * f + 1] == 0 ||
        !edge_point_into_face(m, f, edge, T, &u, &v, &nu, &nv))
        continue;
      // Where the face leaves the sphere at the contact (its direction w into the face, across
      // the edge, points away from the centre: t(P) = |P - O|^2 / 2 d.(P - O) grows along w
      // at the rate (P - M).w / d.(P - O)), no smaller sphere touches it next to the contact,
      // and Newton from there only wanders to the face's border. One touching it farther off
      // would hold its contact inside this sphere, where the certification finds it (deeper than
      // the depth; shallower, the sphere stands at the patches' accuracy anyway). Measured
      // on seven parts: none of the 48,000 Newtons this skips changed a result (docs/Solver.md,
      // item 13).
      const PatchEval pe = eval_patch(m, find_patch(m, f, u, v), u, v);
      const real3 w = nu * pe.Du + nv * pe.Dv, away = r->foot - t * d;
      if (dot(away, w) > (real)1e-3 * length(away) * length(w))
        continue;
      const SurfaceSolve ss = surface_newton(m, f, Ohi, Olo, d, u, v, t, scale, stepTol,
        newtonTol, maxIterations, iterations);
      if (valid_surface_solve(m, ownFace, f, &ss, d, scale, newtonTol) &&
        ss.t < r->t * ((real)1 - roundoff))
        *r = surface_result(f, &ss);
    }
  }
  if (vertexEdge >= 0)
    around_vertex(m, ownFace, first.face, vertexEdge, vertexEnd,
      first.type == CONTACT_SURFACE_SURFACE ? first.face : -1, first.t, Ohi, Olo, d, scale,
      stepTol, newtonTol, maxIterations, maxEdgeIterations, iterations, r);
}

// --- the certification against the patches -------------------------
// 1 where the ray from (u, v) in +u crosses segment s's 16 chords an odd number of times.
int chords_cross_odd(const Model* m, int s, real u, real v)
{
  int odd = 0;
  real2 d1, d2;
  real2 a = seg_point(m->trim + TRIM_REALS * s, (real)0, &d1, &d2);
  for (int k = 1; k <= 16; ++k)
  {
    const real2 b = seg_point(m->trim + TRIM_REALS * s, (real)k / (real)16, &d1, &d2);
    // Half-open in v, so that a vertex on the ray counts once.
    if ((a.y > v) != (b.y > v) && a.x + (v - a.y) * (b.x - a.x) / (b.y - a.y) > u)
      odd = !odd;
    a = b;
  }
  return odd;
}

// Whether a box (u0, v0, u1, v1) can hold a crossing of the ray from (u, v) in +u: it spans v
// and reaches past u, with a margin for the chords' rounding (a chord lies in its segment's
// control hull, and so in the box, up to that).
inline int box_meets_ray(__global const real* b, real u, real v, real margin)
{
  return b[1] <= v + margin && b[3] >= v - margin && b[2] >= u - margin;
}

// Even-odd count of the crossings of a ray in +u with the face's trimming loops, each segment
// as 16 chords (as the host's brt::InsideByCrossings): the second opinion for points far from the
// loops. A face with a segment tree (classify's) counts only the segments whose boxes the ray
// meets: the others have no crossing, so the parity, and the answer, are the same.
int inside_by_crossings(const Model* m, int face, real u, real v)
{
  __global const int* fi = m->faceInfo + FACE_INTS * face;
  int inside = 0;
  if (fi[9] >= 0)
  {
    __global const real* fd = m->faceDomain + FACE_REALS * face;
    const real margin = (real)64 * REAL_EPS * (fabs(u) + fabs(v) + fd[1] - fd[0] + fd[3] - fd[2]);
    int stack[32];
    int top = 0;
    stack[top++] = fi[9];
    while (top > 0)
    {
      const int n = stack[--top];
      if (!box_meets_ray(m->trimNodeBox + 4 * n, u, v, margin))
        continue;
      __global const int* ni = m->trimNodeInfo + 3 * n;
      if (ni[1] > 0)
      {
        for (int j = 0; j < ni[1]; ++j)
        {
          const int seg = m->trimItems[2 * (ni[0] + j)];
          if (box_meets_ray(m->trim + TRIM_REALS * seg + 8, u, v, margin) &&
            chords_cross_odd(m, seg, u, v))
            inside = !inside;
        }
        continue;
      }
      if (top + 2 > 32)
        continue; // never: the tree is balanced
      stack[top++] = ni[2];
      stack[top++] = n + 1;
    }
    return inside;
  }
  for (int l = fi[4]; l < fi[4] + fi[5]; ++l)
  {
    const int first = m->loops[2 * l], count = m->loops[2 * l + 1];
    for (int s = first; s < first + count; ++s)
      if (chords_cross_odd(m, s, u, v))
        inside = !inside;
  }
  return inside;
}

// The deepest point found so far: the point itself, its face and (u, v) there (a start for the
// restart), its edge and T when it lies on an edge (-1 otherwise), and eq. 1's radius through it
// with the depth as clearance.
typedef struct
{
  real best; // its distance from the centre M
  int found, face, edge;
  int onTrim; // a face's point on its trim (within rounding), not inside it: where the face ends
  real u, v, t, T;
  real3 w; // the point, relative to O
  // The last trim test's point on face trimFace and the square of a radius about it that no
  // trimming curve enters (classify_clear; a thousandth of it kept as margin, and on the
  // outside the trim's rounding), and whether it counted: the points of that disk count or not
  // alike without a trim test of their own (consider_point).
  int trimFace, trimIn;
  real trimU, trimV, trimR2;
} PointInside;

// Squared distance from p to a box (min x, y, z, max x, y, z); p and the box relative to the
// model's centre.
inline real box_gap2(__global const real* b, real3 p)
{
  const real3 e = max(max(make_real3(b[0], b[1], b[2]) - p, splat_real3(0)),
    p - make_real3(b[3], b[4], b[5]));
  return dot(e, e);
}

// How much deeper than another face's a point of O's own face must lie to count: twice the
// tolerance (a slack), since O lies on the exact surface and the patches up to a tolerance off it;
// nothing where the patches are the face's surface (FACE_INTS slot 10), which O lies on.
inline real own_face_margin(const Model* m, int face)
{
  return m->faceInfo[FACE_INTS * face + 10] ? (real)0 : m->slack;
}

// The margin within half the radius of O on a face without an exact surface, where a point of
// O's own face lies inside the sphere only by the face curving more than the sphere or by the
// patches' error: in double the face's measured deviation (FACE_DEVIATION) and half as much
// again, as deviation_allowance takes it, never more than the slack (the slack hid such a face
// 3.7e-4 mm deep; docs/Solver.md, item 14, "O's own free-form face near O"). Elsewhere, in float
// and where no measure came, the slack: a face with an exact surface curves into the sphere as
// its closed form says (self_contact_radius), and farther from O the own face is the wall
// across, where the slack also covers its trim's approximation (the measure there shrank exact
// spheres by up to 1.2e-3 relative on Voron-0's RPi DIN mount, Ploopy's headbands and trackpad).
inline real own_face_margin_near(const Model* m, int face)
{
  const real margin = own_face_margin(m, face);
#ifdef BRT_DOUBLE
  const real measured = m->faceDomain[FACE_REALS * face + FACE_DEVIATION];
  if (measured >= (real)0 && m->faceInfo[FACE_INTS * face + 8] == EXACT_NONE)
    return fmin(margin, (real)1.5 * measured + (real)1e-3 * m->slack);
#endif
  return margin;
}

// A candidate point w = P - O on `face` at (u, v), the centre at M = O + mr: kept when it lies
// inside the trim, deeper than the depth in d, deeper than the best so far, and not the sample's
// own point: on O's own face a point must lie deeper by twice the tolerance more (the patches
// there may lie a little more than the tolerance off O's exact point: a toroidal shell converted
// within 1e-6 showed 2.75e-6 at O's own patch point), unless its patches are its surface
// (own_face_margin; within half the radius of O on a free-form face, its measured deviation:
// own_face_margin_near), and within 4 tolerances of O nothing counts.
BRT_SPLIT void consider_point(const Model* m, int ownFace, int face, real u, real v, real3 w, real3 mr,
  real3 d, real depth, real reach, PointInside* st)
{
  const real dist = length(w - mr);
  if (!(dist < st->best))
    return;
  // The cheap tests first, then the trim test.
  const real dn = dot(d, w);
  const real tol = (real)0.5 * m->slack;
  if (!(dn > depth) ||
    (face == ownFace &&
      !(dist < reach -
          (dot(w, w) < (real)0.25 * dot(mr, mr) ? own_face_margin_near(m, face)
                                                 : own_face_margin(m, face)))) ||
    dot(w, w) <= (real)16 * tol * tol)
    return;
  __global const real* fd = m->faceDomain + FACE_REALS * face;
  int seg;
  real param, trimDist;
  // A point far from the loops also passes the crossing test: the nearest-segment test can
  // misjudge a point equidistant from several parts of a loop (seen at a face's UV corner). A
  // point on the trim within rounding (1e-9 of the domain) is on the face (its boundary belongs
  // to it): the nearest point of a face often lies on its trim, where the side test is a coin
  // flip.
  const real size = fd[1] - fd[0] + fd[3] - fd[2];
  int inTrim = 1;
  if (!(face == st->trimFace &&
        (u - st->trimU) * (u - st->trimU) + (v - st->trimV) * (v - st->trimV) < st->trimR2))
  {
    real clear2;
    inTrim = classify_clear(m, face, make_real2(u, v), &seg, &param, &trimDist, &clear2);
    const real onTrim = (real)1e-9 * size;
    if (!(inTrim || trimDist <= onTrim))
    {
      // Outside beyond the trim's rounding: so is every point nearer than clear - onTrim.
      const real r = sqrt(clear2) - onTrim;
      st->trimFace = r > (real)0 ? face : -1;
      st->trimU = u;
      st->trimV = v;
      st->trimR2 = (real)0.998 * r * r;
      st->trimIn = 0;
      return;
    }
    if (trimDist > (real)1e-3 * size && !inside_by_crossings(m, face, u, v))
      return;
    if (inTrim)
    {
      st->trimFace = face;
      st->trimU = u;
      st->trimV = v;
      st->trimR2 = (real)0.998 * clear2;
      st->trimIn = 1;
    }
  }
  else if (!st->trimIn)
    return;
  st->best = dist;
  st->found = 1;
  st->face = face;
  st->edge = -1;
  st->onTrim = !inTrim;
  st->u = u;
  st->v = v;
  st->t = (real)0.5 * (dot(w, w) - depth * depth) / (dn - depth);
  st->w = w;
}

// The nearest point of patch p to the centre: a 5x5 grid (its points inside the trim are
// candidates themselves), then Newton on |S - M|^2 / 2 in (u, v), clamped to the patch.
// Newton on |S - M|^2 / 2 over patch p from (u0, v0), clamped to the patch (certify_patch): the
// nearest of its points in (*nu, *nv). Returns 1 where it converged, 0 where it stopped at its
// cap of steps (or a singular step) still getting nearer; *concave says whether a step found
// the distance not convex (Gauss-Newton's), and alongValley lengthens those steps (below).
int patch_nearest_newton(const Model* m, int p, real3 anchor, real3 mr, real u0, real v0,
  int alongValley, real* outU, real* outV, int* concave)
{
  __global const real* pd = m->patchDomain + 4 * p;
  real u = u0, v = v0;
  // Newton stops where it no longer gets nearer by a thousandth of the slack (a flat minimum: O's
  // own round, which the sphere touches along the arc, took all 8 steps on most of its patches);
  // the nearest of its points is kept.
  // A step that lands farther than the point it left overshot (a patch that bends much within
  // the step: Newton's quadratic model holds only near the minimum) and is halved back towards
  // that point, up to four times, before Newton gives up there. Stopping at the first such step
  // kept the grid's point: on a Charybdis keyboard case (a ruled B-spline wall whose section
  // bulges 2.5 mm) the wall 0.99 mm inside a sphere of radius 1 went unseen, and the sphere
  // stood, 58 times the exact thickness.
  real last = REAL_MAX, nearU = u, nearV = v, fromU = u, fromV = v;
  int halvings = 0, converged = 0;
  *concave = 0;
  for (int it = 0;; ++it)
  {
    const PatchEval e = eval_patch(m, p, u, v);
    const real3 w = anchor + e.P - mr;
    const real dist = length(w);
    if (dist < last)
    {
      nearU = u;
      nearV = v;
    }
    if (it == 8 + halvings) // 8 steps, the last one measured
      break;
    if (!(last - dist > (real)1e-3 * m->slack))
    {
      // (Farther by rounding only: converged.)
      converged = !(dist - last > (real)1e-3 * m->slack);
      if (converged || halvings == 4)
        break;
      ++halvings;
      u = (real)0.5 * (fromU + u);
      v = (real)0.5 * (fromV + v);
      continue;
    }
    last = dist;
    fromU = u;
    fromV = v;
    const real g0 = dot(e.Du, w), g1 = dot(e.Dv, w);
    real h00 = dot(e.Du, e.Du) + dot(e.Duu, w), h01 = dot(e.Du, e.Dv) + dot(e.Duv, w),
         h11 = dot(e.Dv, e.Dv) + dot(e.Dvv, w);
    real det = h00 * h11 - h01 * h01;
    // The Hessian's own terms, for the valley's direction below.
    const real H00 = h00, H01 = h01, H11 = h11;
    int gaussNewton = 0;
    if (!(h00 > (real)0) || !(det > (real)0))
    {
      // Not convex here: Gauss-Newton.
      h00 = dot(e.Du, e.Du);
      h01 = dot(e.Du, e.Dv);
      h11 = dot(e.Dv, e.Dv);
      det = h00 * h11 - h01 * h01;
      gaussNewton = 1;
      *concave = 1;
    }
    real nu, nv;
    if (det > (real)0)
    {
      // Where the step would leave the patch across a side that u (or v) lies on, u stays there
      // and v takes Newton's step for v alone (the problem reduced to that side). The full step,
      // clamped back onto the side, moved v by an amount that assumed u moved too, and landed
      // farther nearly always; the halvings after it found nothing: 71,454 of the small
      // headband's 388,174 searches ended so, each after five evaluations more (forty-fifth
      // session, counters in a throwaway build; with this, 1,518,140 -> 1,164,477 patch
      // evaluations there, 877,962 -> 494,531 on the RPi DIN mount). Holding a coordinate
      // wherever the distance falls outwards (the gradient's sign alone) was tried first: it
      // stopped where the full step would have gone inwards, and spheres grew through the
      // boundary (Bastardkb's CMini, sample 24526: 2t = 0.0081 -> 2.24, 0.13 mm too deep).
      const real su = -(h11 * g0 - h01 * g1) / det, sv = -(h00 * g1 - h01 * g0) / det;
      const int leavesU = (u <= pd[0] && su < (real)0) || (u >= pd[1] && su > (real)0);
      const int leavesV = (v <= pd[2] && sv < (real)0) || (v >= pd[3] && sv > (real)0);
      nu = leavesU ? u : clamp(u + (leavesV ? -g0 / h00 : su), pd[0], pd[1]);
      nv = leavesV ? v : clamp(v + (leavesU ? -g1 / h11 : sv), pd[2], pd[3]);
    }
    else if (h00 <= (real)1e-12 * h11 && h11 > (real)0)
    {
      // u's derivative vanishes (a side of the patch collapsed to a point: a sphere's pole, a
      // cone's apex), where the grid's nearest point often lies: a step along v alone moves off
      // it, and the full step follows from there. Newton stopped at a pole before, and a point
      // of the patch 0.43 mm deep in a sphere of radius 0.5 went unseen (OpenCASCADE's
      // trj3_s1-md-214.stp, sample 1796).
      nu = u;
      nv = clamp(v - g1 / h11, pd[2], pd[3]);
    }
    else if (h11 <= (real)1e-12 * h00 && h00 > (real)0)
    {
      nu = clamp(u - g0 / h00, pd[0], pd[1]);
      nv = v;
    }
    else
      break;
    if (gaussNewton && alongValley)
    {
      // Concave here, as along a ring the sphere osculates: Gauss-Newton's step, sized by the
      // metric alone, is far too short there. From its point, the step goes on along the
      // valley's soft direction (the coordinate whose reduced curvature, h00 - h01^2 / h11 or
      // h11 - h01^2 / h00, is not positive, the other following the valley: -h01 / h11), doubled
      // while the distance falls, up to 2^10 times Gauss-Newton's step (certify_patch;
      // docs/Solver.md, "The certification's Newton along a valley").
      real du = nu - u, dv = nv - v;
      if (H11 > (real)0 && !(H00 - H01 * H01 / H11 > (real)0))
        dv = -H01 / H11 * du;
      else if (H00 > (real)0 && !(H11 - H01 * H01 / H00 > (real)0))
        du = -H01 / H00 * dv;
      const real u1 = nu, v1 = nv;
      real prev = length(anchor + eval_patch_point(m, p, nu, nv) - mr);
      for (int k = 0; k < 10 && (du != (real)0 || dv != (real)0); ++k)
      {
        const real f = (real)((2 << k) - 1);
        const real tu = clamp(u1 + f * du, pd[0], pd[1]), tv = clamp(v1 + f * dv, pd[2], pd[3]);
        const real dk = length(anchor + eval_patch_point(m, p, tu, tv) - mr);
        if (!(dk < prev))
          break;
        prev = dk;
        nu = tu;
        nv = tv;
      }
    }
    const int done =
      fabs(nu - u) / (pd[1] - pd[0]) + fabs(nv - v) / (pd[3] - pd[2]) < (real)1e-12;
    u = nu;
    v = nv;
    if (done)
    {
      nearU = u;
      nearV = v;
      converged = 1;
      break;
    }
  }
  *outU = nearU;
  *outV = nearV;
  return converged;
}

// The cubic Bernstein values at k / n, k = 0..n, for a grid over a patch (certify_patch).
inline void grid_bernstein(int n, real (*B)[4])
{
  for (int k = 0; k <= n; ++k)
  {
    const real x = (real)k / (real)n, y = (real)1 - x;
    B[k][0] = y * y * y;
    B[k][1] = (real)3 * y * y * x;
    B[k][2] = (real)3 * y * x * x;
    B[k][3] = x * x * x;
  }
}

// A grid's row over the patch's control points c: each column of the control net against the
// u row's Bernstein values Bu (then the v values give the row's points).
inline void grid_row(__global const real* c, const real* Bu, real3* row)
{
  for (int j = 0; j < 4; ++j)
  {
    row[j] = splat_real3(0);
    for (int a = 0; a < 4; ++a)
    {
      const int k = (4 * a + j) * 3;
      row[j] += Bu[a] * make_real3(c[k], c[k + 1], c[k + 2]);
    }
  }
}

// Newton's nearest point (u, v) of patch p, clamped to the face's own parameter border where the
// face's nearest point to M lies beyond it, was passed over (off the trim, which runs along that
// border, or not deep enough): the face's point a thousandth of the patch inside the border is
// asked too. Where that border is an edge of O's own face, the edge's points count only a slack
// deeper than the face's (certify_edge), and the face's points next to it were never asked: the
// unseen FRAMEWORK cover's face 24 held a sphere of its neighbour face 488 3.9e-4 mm deep along
// their common edge, 0.04 mm from O (sample 57651; docs/Solver.md, "A face's border along O's own
// edge"). Not across a seam (a periodic parameter), where the border is inside the face.
inline void consider_inside_face_border(const Model* m, int p, int ownFace, int face, real3 anchor,
  real u, real v, real3 w, real3 mr, real3 d, real depth, real reach, PointInside* st)
{
  __global const real* pd = m->patchDomain + 4 * p;
  __global const real* fd = m->faceDomain + FACE_REALS * face;
  const int lowU = !(fd[4] > (real)0) && u <= fd[0], highU = !(fd[4] > (real)0) && u >= fd[1];
  const int lowV = !(fd[5] > (real)0) && v <= fd[2], highV = !(fd[5] > (real)0) && v >= fd[3];
  if (!(lowU || highU || lowV || highV) || !(length(w - mr) < st->best))
    return;
  const real hu = (real)1e-3 * (pd[1] - pd[0]), hv = (real)1e-3 * (pd[3] - pd[2]);
  const real nu = lowU ? u + hu : (highU ? u - hu : u), nv = lowV ? v + hv : (highV ? v - hv : v);
  const real3 wn = anchor + eval_patch_point(m, p, nu, nv);
  consider_point(m, ownFace, face, nu, nv, wn, mr, d, depth, reach, st);
}

BRT_SPLIT void certify_patch(const Model* m, int p, int ownFace, real3 Ohi, real3 Olo, real3 d, real3 mr,
  real depth, real reach, PointInside* st)
{
  const int face = m->patchFace[p];
  __global const real* pd = m->patchDomain + 4 * p;
  const real3 anchor = anchor_minus(m->patchAnchor + 6 * p, Ohi, Olo);
  __global const real* c = m->patches + 48 * p;
  real bu = (real)0.5 * (pd[0] + pd[1]), bv = (real)0.5 * (pd[2] + pd[3]), bd = REAL_MAX;
  // On O's own face whose patches are its surface (below): O's (u, v), the sample's own where a
  // chain carries it (a patch that does not hold it has nothing to do there), else the grid
  // point nearest O, from which Newton towards O finds it.
  const int ownExact = face == ownFace && m->faceInfo[FACE_INTS * face + 10];
  const int ownKnown = ownExact && m->memo && m->memo->ownFace == ownFace;
  const int holdsO = ownKnown && m->memo->ownU >= pd[0] && m->memo->ownU <= pd[1] &&
    m->memo->ownV >= pd[2] && m->memo->ownV <= pd[3];
  real ou = bu, ov = bv, od = REAL_MAX;
  // The grid's squared distances from M (REAL_MAX within 4 tolerances of O), for a second
  // Newton from another of its local minima (below), and the start's place in it.
  real gridD[25];
  int startAt = -1;
  // The grid's points by the tensor product in two stages, the Bernstein values at 0, 1/4, 1/2,
  // 3/4 and 1 computed once: each row of control points against the u values, then the v values.
  real B[5][4];
  grid_bernstein(4, B);
  for (int i = 0; i <= 4; ++i)
  {
    real3 row[4];
    grid_row(c, B[i], row);
    for (int j = 0; j <= 4; ++j)
    {
      const real u = pd[0] + (real)0.25 * (real)i * (pd[1] - pd[0]);
      const real v = pd[2] + (real)0.25 * (real)j * (pd[3] - pd[2]);
      const real3 w = anchor + (B[j][0] * row[0] + B[j][1] * row[1] + B[j][2] * row[2] + B[j][3] * row[3]);
      // Newton's start: the nearest grid point but O's own (within 4 tolerances of O, where
      // nothing counts: consider_point). O is a stationary point of the distance from M (the
      // sphere is tangent there), so Newton started there stays; a grazing face's deeper points
      // a little farther off went unseen (OpenCASCADE's bug33398.step, sample 31641: O's own
      // B-spline face 7.3e-4 mm inside a sphere of radius 1.44, 0.21 from O).
      const real dd = dot(w - mr, w - mr);
      const int nearOwnPoint = dot(w, w) <= (real)4 * m->slack * m->slack;
      gridD[5 * i + j] = nearOwnPoint ? REAL_MAX : dd;
      if (dd < bd && !nearOwnPoint)
      {
        bd = dd;
        bu = u;
        bv = v;
        startAt = 5 * i + j;
      }
      if (ownExact && !ownKnown && dot(w, w) < od)
      {
        od = dot(w, w);
        ou = u;
        ov = v;
      }
      if (dd < st->best * st->best)
        consider_point(m, ownFace, face, u, v, w, mr, d, depth, reach, st);
    }
  }
  // The diagonal of the grid's box, packed (PATCH_HULL_REALS): the box taken here, point by
  // point, was about 4% of the small Ploopy headband's solve (perf, a -g build); packed, the
  // solve alone 4-11% faster there, 3-7% on the RPi DIN mount (best of 10, two threads, two
  // interleaved rounds; results the same on all 56 solve dumps).
  const real extent = m->patchHull[PATCH_HULL_REALS * p + 9];
  real nearU, nearV;
  int concave;
  int converged = patch_nearest_newton(m, p, anchor, mr, bu, bv, 0, &nearU, &nearV, &concave);
  real3 wn = anchor + eval_patch_point(m, p, nearU, nearV);
  const real bestBefore = st->best;
  consider_point(m, ownFace, face, nearU, nearV, wn, mr, d, depth, reach, st);
  if (st->best == bestBefore)
    consider_inside_face_border(m, p, ownFace, face, anchor, nearU, nearV, wn, mr, d, depth, reach,
      st);
  // Newton stopped at its cap still getting nearer after a concave step: along a valley that the
  // sphere osculates, its steps crept (a 1 mm bore's ring, 4e-4 to 6e-4 inside the sphere 0.35
  // to 0.46 from O, missed). It goes on from its nearest point with the valley's longer steps.
  // Only there: Newton with them throughout moved results on 31 of 119 solve dumps, some
  // spheres growing where it left one basin for another.
  if (!converged && concave)
  {
    converged = patch_nearest_newton(m, p, anchor, mr, nearU, nearV, 1, &nearU, &nearV, &concave);
    wn = anchor + eval_patch_point(m, p, nearU, nearV);
    consider_point(m, ownFace, face, nearU, nearV, wn, mr, d, depth, reach, st);
  }
  // Where Newton ended just outside the sphere (within a thousandth of the radius), not
  // converged or on the patch's border, on O's own face or a face with no exact surface,
  // finding nothing, the distance from M is nearly flat over the patch (a face curving with the
  // sphere), and another of the grid's basins may hold the deeper point: Newton again from the
  // grid's nearest point not next to the start, where that is a local minimum of the grid (a
  // local minimum nearer than it and not next to the start cannot be) within a hundredth of the
  // radius. The SO-ARM101 base's own B-spline face dipped 1.2e-3 mm into a sphere of radius
  // 2.49 between two rows of the grid, whose nearest point led Newton to the patch's border
  // 0.0009 outside (docs/Solver.md, "Accuracy", "A second basin of the grid").
  if (st->best == bestBefore &&
    (face == ownFace || m->faceInfo[FACE_INTS * face + 8] == EXACT_NONE) &&
    (!converged || !(nearU > pd[0] && nearU < pd[1] && nearV > pd[2] && nearV < pd[3])) &&
    length(wn - mr) < reach * (real)1.001)
  {
    const real window = reach * (real)1.01;
    // The nearest grid point not next to the start, where it is a local minimum: a nearer local
    // minimum not next to the start would have been nearer.
    const int si = startAt / 5, sj = startAt % 5;
    int second = -1;
    real secondD = window * window;
    for (int k = 0; k < 25; ++k)
    {
      const int di = k / 5 - si, dj = k % 5 - sj;
      const int away = di * di > 1 || dj * dj > 1;
      second = away && gridD[k] < secondD ? k : second;
      secondD = away && gridD[k] < secondD ? gridD[k] : secondD;
    }
    if (second >= 0)
    {
      const int i = second / 5, j = second % 5;
      for (int a = i - 1; a <= i + 1; ++a)
        for (int b = j - 1; b <= j + 1; ++b)
          if (a >= 0 && a <= 4 && b >= 0 && b <= 4 && gridD[5 * a + b] < secondD)
            second = -1;
    }
    if (second >= 0)
    {
      real su, sv;
      int c2;
      patch_nearest_newton(m, p, anchor, mr,
        pd[0] + (real)0.25 * (real)(second / 5) * (pd[1] - pd[0]),
        pd[2] + (real)0.25 * (real)(second % 5) * (pd[3] - pd[2]), 0, &su, &sv, &c2);
      const real3 w2 = anchor + eval_patch_point(m, p, su, sv);
      consider_point(m, ownFace, face, su, sv, w2, mr, d, depth, reach, st);
    }
  }
  // O's own face, where its patches are its surface and this patch holds O: where the face
  // curves more than the sphere in some direction at O, O is a saddle or a maximum of the
  // distance from M, and points of the face next to O lie inside the sphere; a Newton from a grid
  // point on the line of O's other direction stays on it and ends at O, and the grids may have no
  // point in the dip (fifty-second session: CubicRidge's top curving 2% more than the sphere at
  // its crest, up to 1.4e-3 mm deep within 0.28 of the radius of O, went unseen on a patch 16 mm
  // wide, also with the finer grid counting such a face from O on, below). From O's
  // point on the patch, the Hessian of |S - M|^2 / 2 in (u, v); along its eigenvector of a
  // negative eigenvalue, Newton from four starts, a twentieth and three twentieths of the radius
  // from O each way. Only on such faces: on patches that approximate their face, the curvature
  // at O is the patches' and not the face's (docs/Solver.md, Open items, "Own-face osculating
  // contacts, tried again").
  if (ownExact && (!ownKnown || holdsO))
  {
    real uo = ownKnown ? m->memo->ownU : ou, vo = ownKnown ? m->memo->ownV : ov;
    int c0;
    if (!ownKnown)
      patch_nearest_newton(m, p, anchor, splat_real3(0), ou, ov, 0, &uo, &vo, &c0);
    const PatchEval e = eval_patch(m, p, uo, vo);
    const real3 w0 = anchor + e.P;
    if (dot(w0, w0) <= m->slack * m->slack)
    {
      const real3 q = w0 - mr;
      const real h11 = dot(e.Du, e.Du) + dot(q, e.Duu), h12 = dot(e.Du, e.Dv) + dot(q, e.Duv),
                 h22 = dot(e.Dv, e.Dv) + dot(q, e.Dvv);
      const real mid = (real)0.5 * (h11 + h22), dif = (real)0.5 * (h11 - h22);
      const real lambda = mid - sqrt(dif * dif + h12 * h12);
      if (lambda < (real)-1e-6 * (fabs(h11) + fabs(h22)))
      {
        // The eigenvector of lambda, from the row of H - lambda I with the larger entries.
        real eu = h12, ev = lambda - h11;
        if (fabs(h22 - lambda) + fabs(h12) > fabs(ev) + fabs(eu))
        {
          eu = lambda - h22;
          ev = h12;
        }
        const real step = length(eu * e.Du + ev * e.Dv);
        for (int k = 0; k < 4 && step > (real)0; ++k)
        {
          const real s = (k < 2 ? (real)0.05 : (real)0.15) * length(mr) / step * ((k & 1) ? -1 : 1);
          const real su = clamp(uo + s * eu, pd[0], pd[1]), sv = clamp(vo + s * ev, pd[2], pd[3]);
          real nu, nv;
          int c1;
          patch_nearest_newton(m, p, anchor, mr, su, sv, 0, &nu, &nv, &c1);
          const real3 wk = anchor + eval_patch_point(m, p, nu, nv);
          consider_point(m, ownFace, face, nu, nv, wk, mr, d, depth, reach, st);
        }
      }
    }
  }
  // A face that grazes the sphere along a valley of a patch much larger than the sphere: Newton
  // from the 5 x 5 grid's nearest point ends at the valley's shallow end, just outside the sphere,
  // and its deep point lies between the grid's points (Voron's corner_ptfe_plate: a 7 mm patch, a
  // sphere of radius 0.6, O's own face 5.5e-4 inside), or runs back to O, the distance's local
  // minimum, from a grid point on the far side of O from the valley (the grabcad pulley guard:
  // its own face 1.4e-3 inside 0.36 from O, Newton ending 0.07 from O). Where Newton ends within
  // a thousandth of the radius outside the sphere on a patch whose grid spans more than the
  // radius, a grid of about a quarter of the radius (up to 9 x 9) and Newton from its nearest
  // point, both counting only points three tenths of the radius or more from O. Nearer O the face
  // osculates the sphere and the patches' error decides: counted from a tenth of the radius on,
  // the unseen cover's extruded face 24 gave points 3.8e-4 deep 0.098 from O where OpenCASCADE
  // has none, and ten exact spheres failed NotMaximal.
  // Another face's patch with no exact surface gets the finer grid too where Newton ends on the
  // patch's border at the sphere (forty-fourth session): a bend of Bastardkb's charybdisnano case,
  // one patch 18 mm wide, touched a sphere of radius 2 where Newton ended and dipped 0.086 mm into
  // it in its other valley, between the grid's points (2t = 4 stood where the exact thickness is
  // 3.909). Its points count from O on (the grid's exclusion is for O's own face).
  // So does one whose Newton stopped at its cap still getting nearer (forty-fifth session): on a
  // B-spline fillet of Bastardkb's Charybdis3 case, narrow across and flat along, Newton's first
  // step jumped past the valley's deepest point to the patch's border, and each step from there
  // crept back by 0.002 of the patch until the cap, 0.001 outside the sphere, where the valley
  // dips 0.0011 into it (2t = 4.00872 where the exact thickness is 4.00309).
  // Where O's own face's patches are its surface (FACE_INTS slot 10: no patch error to decide),
  // its points count from consider_point's 4 tolerances of O on (fifty-second session): a
  // B-spline fillet of a die-cast box (Hammond's 1590T) dipped 5.8e-4 mm into a sphere 0.25 of
  // its radius from O, between the 5 x 5 grid's points, and the sphere read 2t = 3.987 where the
  // exact thickness is 3.924.
  const real dn = length(wn - mr);
  const real nearO = face != ownFace ? (real)-1
    : m->faceInfo[FACE_INTS * face + 10] ? (real)4 * m->slack * m->slack
                                         : (real)0.09 * reach * reach; // (0.3 of the radius)^2
  const int onBorder = !(nearU > pd[0] && nearU < pd[1] && nearV > pd[2] && nearV < pd[3]);
  if ((face == ownFace ||
        ((onBorder || !converged) && m->faceInfo[FACE_INTS * face + 8] == EXACT_NONE)) &&
    dn < reach * (real)1.001 && extent > reach)
  {
    // By the tensor product in two stages, as the 5 x 5 grid above: evaluating each point apart
    // (eval_patch_point) made the whole solve of Ploopy's small headband 8% slower (a timing
    // driver on its solve dump, best of 10, two threads, two interleaved rounds).
    const int n = (int)clamp(ceil((real)4 * extent / reach), (real)5, (real)8);
    real fu = nearU, fv = nearV, fd = REAL_MAX;
    real Bn[9][4];
    grid_bernstein(n, Bn);
    for (int i = 0; i <= n; ++i)
    {
      real3 row[4];
      grid_row(c, Bn[i], row);
      for (int j = 0; j <= n; ++j)
      {
        const real u = pd[0] + (pd[1] - pd[0]) * (real)i / (real)n;
        const real v = pd[2] + (pd[3] - pd[2]) * (real)j / (real)n;
        const real3 w =
          anchor + (Bn[j][0] * row[0] + Bn[j][1] * row[1] + Bn[j][2] * row[2] + Bn[j][3] * row[3]);
        if (!(dot(w, w) > nearO))
          continue;
        const real dd = dot(w - mr, w - mr);
        if (dd < fd)
        {
          fd = dd;
          fu = u;
          fv = v;
        }
        if (dd < st->best * st->best)
          consider_point(m, ownFace, face, u, v, w, mr, d, depth, reach, st);
      }
    }
    if (fd < REAL_MAX)
    {
      const int fineConverged =
        patch_nearest_newton(m, p, anchor, mr, fu, fv, 0, &nearU, &nearV, &concave);
      real3 w = anchor + eval_patch_point(m, p, nearU, nearV);
      if (dot(w, w) > nearO)
        consider_point(m, ownFace, face, nearU, nearV, w, mr, d, depth, reach, st);
      if (!fineConverged && concave)
      {
        patch_nearest_newton(m, p, anchor, mr, nearU, nearV, 1, &nearU, &nearV, &concave);
        w = anchor + eval_patch_point(m, p, nearU, nearV);
        if (dot(w, w) > nearO)
          consider_point(m, ownFace, face, nearU, nearV, w, mr, d, depth, reach, st);
      }
    }
  }
}

// The nearest point of edge segment es to the centre (a 9-point grid, then Newton in T, clamped):
// where a face's part inside the sphere ends at its trim (a corner cutting in), the deepest
// point lies on an edge; the restart starts from it, moved a hair into a face.
void certify_edge(const Model* m, int es, int ownFace, real3 Ohi, real3 Olo, real3 d, real3 mr,
  real depth, real reach, PointInside* st)
{
  const int edge = m->edgeSegEdge[es];
  const real T0 = m->edgeSegRange[2 * es], T1 = m->edgeSegRange[2 * es + 1];
  real3 C, Ct, Ctt;
  real T = T0, bd = REAL_MAX;
  for (int i = 0; i <= 8; ++i)
  {
    const real Ti = T0 + (T1 - T0) * (real)i / (real)8;
    eval_edge_near(m, edge, es, Ti, Ohi, Olo, &C, &Ct, &Ctt);
    if (dot(C - mr, C - mr) < bd)
    {
      bd = dot(C - mr, C - mr);
      T = Ti;
    }
  }
  for (int it = 0; it < 8; ++it)
  {
    eval_edge_near(m, edge, es, T, Ohi, Olo, &C, &Ct, &Ctt);
    const real3 w = C - mr;
    const real g = dot(Ct, w), h = dot(Ct, Ct) + dot(Ctt, w);
    const real h2 = h > (real)0 ? h : dot(Ct, Ct);
    if (!(h2 > (real)0))
      break;
    const real next = clamp(T - g / h2, fmin(T0, T1), fmax(T0, T1));
    const int done = fabs(next - T) <= (real)1e-12 * (fabs(T) + (real)1);
    T = next;
    if (done)
      break;
  }
  eval_edge_near(m, edge, es, T, Ohi, Olo, &C, &Ct, &Ctt);
  const real dist = length(C - mr);
  const real dn = dot(d, C);
  const int f0 = m->edgeInfo[4 * edge + 2], f1 = m->edgeInfo[4 * edge + 3];
  const real tol = (real)0.5 * m->slack;
  if (!(dist < st->best) || !(dn > depth) ||
    ((f0 == ownFace || f1 == ownFace) && !(dist < reach - (real)2 * tol)) ||
    dot(C, C) <= (real)16 * tol * tol)
    return;
  // The point counts whether or not a face's trim covers T (a file whose trims fall short of
  // their edge); the restart's start is then the middle of the domain of a face with patches.
  int start = -1;
  real su = 0, sv = 0;
  for (int k = 0; k < 2; ++k)
  {
    const int face = k == 0 ? f0 : f1;
    if (face < 0 || m->faceInfo[FACE_INTS * face + 1] * m->faceInfo[FACE_INTS * face + 2] == 0)
      continue;
    __global const real* fd = m->faceDomain + FACE_REALS * face;
    real u, v, nu, nv;
    if (edge_point_into_face(m, face, edge, T, &u, &v, &nu, &nv))
    {
      const real hair = (real)1e-6 * (fd[1] - fd[0] + fd[3] - fd[2]);
      start = face;
      su = u + hair * nu;
      sv = v + hair * nv;
      break;
    }
    if (start < 0)
    {
      start = face;
      su = (real)0.5 * (fd[0] + fd[1]);
      sv = (real)0.5 * (fd[2] + fd[3]);
    }
  }
  if (start < 0)
    return;
  st->best = dist;
  st->found = 1;
  st->face = start;
  st->edge = edge;
  st->onTrim = 0;
  st->u = su;
  st->v = sv;
  st->T = T;
  st->t = (real)0.5 * (dot(C, C) - depth * depth) / (dn - depth);
  st->w = C;
}

// A lower bound of the distance from the centre M to a Bezier piece with n control points c
// (relative to the piece's anchor, a = anchor - M): the piece lies in the hull of its control
// points, so none of its points is nearer to M than the least of their offsets along a unit
// direction u. Cheaper than the search by far, and tight where the piece is flat across u: a
// wall tangent to the sphere, O's own patch.
inline real hull_gap(__global const real* c, int n, real3 a, real3 u)
{
  real g = REAL_MAX;
  for (int i = 0; i < n; ++i)
    g = min(g, dot(a + make_real3(c[3 * i], c[3 * i + 1], c[3 * i + 2]), u));
  return g;
}

// The unit direction from M to the mean of the control points (zero where they meet at M).
inline real3 toward_hull(__global const real* c, int n, real3 a)
{
  real3 s = splat_real3(0);
  for (int i = 0; i < n; ++i)
    s += make_real3(c[3 * i], c[3 * i + 1], c[3 * i + 2]);
  s = a + s / (real)n;
  const real l = length(s);
  return l > (real)0 ? s / l : splat_real3(0);
}

// hull_gap of patch p (a = anchor - M) along its mean normal (the cross product of its control
// net's diagonals, turned away from M) and towards its control points' mean: the larger bound;
// *ahead gets the control points' farthest offset along d from O (mr = M - O), which bounds the
// patch's. The mean, the normal and the control points' offsets along it come packed
// (PATCH_HULL_REALS; the host computes the mean and the normal as this did, by the same
// operations), so one pass over the control points does (two, with the normal's offsets, took
// 2.3% more of NIST_MBE_PMI_11's instructions).
inline real patch_gap(const Model* m, int p, real3 a, real3 mr, real3 d, real* ahead)
{
  __global const real* c = m->patches + 48 * p;
  __global const real* h = m->patchHull + PATCH_HULL_REALS * p;
  const real3 mean = a + make_real3(h[0], h[1], h[2]);
  const real lm = length(mean);
  const real3 u = lm > (real)0 ? mean / lm : splat_real3(0);
  real far = -REAL_MAX, gu = REAL_MAX;
  for (int i = 0; i < 16; ++i)
  {
    const real3 ci = make_real3(c[3 * i], c[3 * i + 1], c[3 * i + 2]);
    far = max(far, dot(ci, d));
    gu = min(gu, dot(ci, u));
  }
  *ahead = far + dot(a + mr, d);
  gu += dot(a, u);
  const real3 n = make_real3(h[3], h[4], h[5]);
  if (!(h[3] != (real)0 || h[4] != (real)0 || h[5] != (real)0))
    return gu;
  // Along the normal turned away from M (the side of the corners' mean): the hull's nearest
  // offset from M.
  const real an = dot(a, n);
  return max(gu, an + h[8] < (real)0 ? -(an + h[7]) : an + h[6]);
}

// Signed distance from X (relative to the surface's origin) to the exact surface of kind `kind`
// described at e (FACE_EXACT on), and its unit gradient *g. Where X lies on the axis of a surface
// of revolution (at a sphere's centre) the gradient is taken in the meridian half-plane towards
// `hint` (X's offset to a point near the foot): every meridian alike, the foot is the one there
// (a sample at the middle of a round pocket's floor, its sphere touching the wall all round).
// *ok = 0 where the gradient is not defined: on the axis with a zero hint.
inline real exact_distance_towards(
  int kind, __global const real* e, real3 X, real3 hint, real3* g, int* ok)
{
  const real3 a = make_real3(e[6], e[7], e[8]);
  *ok = 1;
  if (kind == EXACT_PLANE)
  {
    *g = a;
    return dot(X, a);
  }
  if (kind == EXACT_SPHERE)
  {
    const real r = length(X);
    const real lh = length(hint);
    *ok = r > (real)0 || lh > (real)0;
    *g = r > (real)0 ? X / r : (lh > (real)0 ? hint / lh : a);
    return r - e[9];
  }
  const real z = dot(X, a);
  const real3 radial = X - z * a;
  const real rho = length(radial);
  // On the axis the direction away from it is undefined, while the distance is still the
  // surface's (every meridian half-plane alike), which the certification's bounds read without
  // the gradient: a sphere inscribed in a rod has its centre there. With a hint, the direction
  // is X's own down to the rounding of its offset (1e-12 of the size: a thousandth of a
  // micrometre on a part 100 mm across), the hint's only below that.
  const real3 hr = hint - dot(hint, a) * a;
  const real lhr = length(hr);
  const int onAxis = !(rho > (real)1e-6 * (fabs(z) + e[9]));
  *ok = !onAxis || lhr > (real)0;
  const real3 er = !onAxis || (lhr > (real)0 && rho > (real)1e-12 * (fabs(z) + e[9]))
    ? radial / rho
    : (lhr > (real)0 ? hr / lhr : a);
  if (kind == EXACT_CYLINDER)
  {
    *g = er;
    return rho - e[9];
  }
  if (kind == EXACT_CONE)
  {
    // The generator rho = R + z tan(angle) in the meridian half-plane, cos and sin in e[10],
    // e[11]: the nappe the face lies on (the packing turns the description where the face lies
    // past the apex, PackExactSurface). The other nappe is exact_bound_distance's.
    *g = *ok ? e[10] * er - e[11] * a : a;
    return (rho - e[9]) * e[10] - z * e[11];
  }
  // Torus: the tube circle of radius e[10] around the circle of radius e[9] (negative: the
  // lemon of a spindle torus, PackExactSurface).
  const real q = rho - e[9];
  const real l = sqrt(q * q + z * z);
  *ok = *ok && l > (real)0;
  *g = *ok ? (q * er + z * a) / l : a;
  return l - e[10];
}

// exact_distance_towards without a hint: *ok = 0 on the axis.
inline real exact_distance(int kind, __global const real* e, real3 X, real3* g, int* ok)
{
  return exact_distance_towards(kind, e, X, make_real3((real)0, (real)0, (real)0), g, ok);
}

// A lower bound of the distance from X to the whole exact surface: |exact_distance|, and for a
// cone also to its other nappe, past the apex, which meets the half-plane on the mirrored line
// rho = -(R + z tan(angle)). A centre past the apex of a flat cone (a countersink) lies near that
// line and far from the generator's: the generator's distance alone is no bound there. Likewise
// a spindle torus (|R| below the tube's radius) meets the half-plane on both tube circles, around
// rho = R and rho = -R: the apple and the lemon (screw.step's head).
inline real exact_bound_distance(int kind, __global const real* e, real3 X)
{
  real3 g;
  int ok;
  const real f = fabs(exact_distance(kind, e, X, &g, &ok));
  if (kind != EXACT_CONE && !(kind == EXACT_TORUS && fabs(e[9]) < e[10]))
    return f;
  const real3 a = make_real3(e[6], e[7], e[8]);
  const real z = dot(X, a);
  const real rho = length(X - z * a);
  if (kind == EXACT_TORUS)
  {
    const real q = rho + e[9];
    return fmin(f, fabs(sqrt(q * q + z * z) - e[10]));
  }
  return fmin(f, fabs((rho + e[9]) * e[10] + z * e[11]));
}

// How far an analytic face's patches may lie from its exact surface, for the bounds below (X: the
// centre relative to the surface's origin, t the radius, for the rounding). In double: the
// reader's measure (FACE_DEVIATION: random points of the face and a grid on every patch; a grid
// four times as fine found at most 1% more on ten parts) and half as much again, plus the
// tolerance within which a B-spline face was recognised as analytic (1e-3 of the conversion
// tolerance, taken twice) and rounding. The contact face of a sphere solved with the clearance
// lies a quarter slack outside the certification's reach: the conversion tolerance (half the
// slack) in place of the measure had every such patch searched (docs/Solver.md). In float, and
// where no measure came (negative), the larger of the measure and the conversion tolerance.
inline real deviation_allowance(const Model* m, int face, real3 X, real t)
{
  const real measured = m->faceDomain[FACE_REALS * face + FACE_DEVIATION];
#ifdef BRT_DOUBLE
  if (measured >= (real)0)
    return (real)1.5 * measured + (real)1e-3 * m->slack + (real)64 * REAL_EPS * (length(X) + t);
#else
  (void)X;
  (void)t;
#endif
  return fmax((real)0.5 * m->slack, measured);
}

// A lower bound of the distance from the centre M (O + mr) to `face`, from its exact surface
// (plane, cylinder, cone, sphere, torus): no point of the face is nearer to M than M's distance
// from the whole surface. Its patches lie within their deviation of it (deviation_allowance),
// which the bound gives up, so that a point of the patches more than that deviation inside the
// sphere still counts. Tight where the sphere touches a round or a boss, where the control
// points' hull is not, and on a rod's axis; negative where the face has no exact surface.
inline real exact_gap(const Model* m, int face, real3 Ohi, real3 Olo, real3 mr, real t)
{
  const int kind = m->faceInfo[FACE_INTS * face + 8];
  if (kind == EXACT_NONE)
    return (real)-1;
  __global const real* e = m->faceDomain + FACE_REALS * face + FACE_EXACT;
  const real3 X = mr - anchor_minus(e, Ohi, Olo);
  return exact_bound_distance(kind, e, X) - deviation_allowance(m, face, X, t);
}

// A lower bound of the distance from M to patch p of a cylindrical face, tighter than exact_gap
// where the sphere's centre lies near the axis (a rod or boss of radius about t: the whole
// cylinder is then about t from M, and exact_gap lets every patch through). The patch lies in the
// hull of its control points, so within the height range and the sector (around the axis) that
// hold them all (PATCH_SECTOR_REALS, packed on the host in double and rounded outwards); a point
// of it within the deviation of the cylinder has its nearest cylinder point in that range and
// sector too. The bound is M's distance from that piece of the cylinder, less the deviation and
// the rounding of M's height and radius here (a few epsilons of the lengths they come from, M
// taken from the patch's own point of the axis, which is packed relative to the patch's anchor:
// in float the patch's and the sphere's lengths, not the model's; the sector's side also the
// rounding of M's direction around the axis, which grows as M nears the axis, where M's distance
// from the whole cylinder, with the heights, bounds instead). Where the heights alone give `need`
// or more, that (the sector is not asked: the caller only compares the bound with need).
inline real cylinder_patch_gap(const Model* m, int p, int face, real3 Ohi, real3 Olo, real3 mr,
  real t, real need)
{
  __global const real* e = m->faceDomain + FACE_REALS * face + FACE_EXACT;
  __global const real* s = m->patchSector + PATCH_SECTOR_REALS * p;
  const real3 ax = make_real3(e[6], e[7], e[8]);
  const real R = e[9];
  const real3 A = anchor_minus(m->patchAnchor + 6 * p, Ohi, Olo); // the patch's anchor - O
  const real3 X = mr - A - make_real3(s[8], s[9], s[10]); // M - the patch's point of the axis
  const real zM = dot(X, ax);
  const real3 rM = X - zM * ax;
  const real rho = length(rM);
  const real dz = zM - clamp(zM, s[0], s[1]);
  const real rounding = (real)8 * REAL_EPS * (length(X) + length(A) + R + t);
  const real allow = deviation_allowance(m, face, X, t);
  real gap = sqrt((rho - R) * (rho - R) + dz * dz) - rounding;
  if (!(gap - allow < need))
    return gap - allow;
  if (s[7] > (real)0 && rho > (real)0)
  {
    // M's direction around the axis outside the sector: the nearest point lies on the sector's
    // side towards M (either where M lies straight across from the sector's middle: the side is
    // taken from the axis, not from M's direction, which is then all rounding).
    const real3 mid = make_real3(s[2], s[3], s[4]);
    const real3 u = rM / rho;
    if (!(dot(u, mid) >= s[5]))
    {
      const real3 perp = cross(ax, mid);
      const real3 w = s[5] * mid + (dot(u, perp) < (real)0 ? -s[6] : s[6]) * perp;
      const real3 g = rM - R * w;
      gap = fmax(gap, sqrt(dot(g, g) + dz * dz) - rounding * ((real)1 + R / rho));
    }
  }
  return gap - allow;
}

// M's distance in a meridian half-plane of a torus from the tube circle of radius r, (qx, qz) its
// position relative to the tube's centre there: from the patch's arc of the tube where it is
// packed (s[7], PATCH_SECTOR_REALS) and M's direction lies outside it, the arc's nearer end; less
// the rounding of that position (and, at the arc's end, of M's direction from the tube's centre,
// which grows as M nears that centre).
inline real tube_arc_gap(__global const real* s, real qx, real qz, real r, real rounding)
{
  const real lq = sqrt(qx * qx + qz * qz);
  real gap = fabs(lq - r) - rounding;
  if (s[7] > (real)0 && lq > (real)0 && !((qx * s[4] + qz * s[5]) >= s[6] * lq))
  {
    // M's direction outside the arc: its nearer end.
    const real d0 = sqrt((qx - r * s[0]) * (qx - r * s[0]) + (qz - r * s[1]) * (qz - r * s[1]));
    const real d1 = sqrt((qx - r * s[2]) * (qx - r * s[2]) + (qz - r * s[3]) * (qz - r * s[3]));
    gap = fmax(gap, fmin(d0, d1) - rounding * ((real)1 + r / lq));
  }
  return gap;
}

// A lower bound of the distance from M to patch p of a toroidal face (a round), tighter than
// exact_gap where the sphere sits inside the tube and the tube continues beyond the face (the
// sphere of a wall next to a round touches it, and the whole tube circle is then about t from
// M), or the round continues around the axis beyond the patch (a ring's round of a large radius,
// split into patches along it: the sphere of a wall next to it touches one or two of them). The
// patch's points lie within the deviation of the torus at their own parameters (the reader's
// measure), and no point of the torus is nearer to M than M's position in its own meridian
// half-plane is to the tube circle; over the patch that is the arc of the angles around the tube
// (v) its domain spans, or for a torus read from a B-spline, whose parameters are not its angles,
// the arc that holds its control hull (TorusArcOfPatch: every point of such a patch lies within
// the deviation of the torus, at its own angle around the tube) (PATCH_SECTOR_REALS, packed on
// the host: the arc's ends as unit vectors, its middle and the cosine of its half-span around
// that, rounded down; s[7] 0 where not packed: a torus whose tube reaches the axis, an arc of
// half the tube or more). Around the axis, those points lie in the wedge that holds the patch's
// control points, widened by the angle the deviation spans (s[8..11]: its middle direction and
// the cosine of its half-angle, rounded down; 0 where not packed, PackDirectionCone): where M's
// direction across the axis lies outside it, the nearest of them lies in the meridian half-plane
// of the wedge's nearer side, and the bound is M's distance from the arc there, with M's offset
// from that half-plane. Less the deviation and the rounding. Negative: no bound. Where the arc
// alone gives `need` or more, that (the wedge is not asked: the caller only compares the bound
// with need).
inline real torus_patch_gap(const Model* m, int p, int face, real3 Ohi, real3 Olo, real3 mr,
  real t, real need)
{
  __global const real* s = m->patchSector + PATCH_SECTOR_REALS * p;
  if (!(s[7] > (real)0) && !(s[11] > (real)0))
    return (real)-1;
  __global const real* e = m->faceDomain + FACE_REALS * face + FACE_EXACT;
  const real3 ax = make_real3(e[6], e[7], e[8]);
  const real R = e[9], r = e[10];
  const real3 X = mr - anchor_minus(e, Ohi, Olo); // M - the torus's centre
  const real z = dot(X, ax);
  const real3 rM = X - z * ax; // M across the axis
  const real rho = length(rM);
  const real rounding = (real)8 * REAL_EPS * (length(X) + R + r + t);
  const real allow = deviation_allowance(m, face, X, t);
  real gap = tube_arc_gap(s, rho - R, z, r, rounding);
  if (!(gap - allow < need))
    return gap - allow;
  if (s[11] > (real)0 && rho > (real)0)
  {
    const real3 mid = make_real3(s[8], s[9], s[10]);
    if (!(dot(rM, mid) >= s[11] * rho))
    {
      // The wedge's nearer side (as cylinder_patch_gap's), M's position in its half-plane and
      // M's offset from that.
      const real3 perp = cross(ax, mid);
      const real sinA = sqrt(fmax((real)1 - s[11] * s[11], (real)0));
      const real3 w = s[11] * mid + (dot(rM, perp) < (real)0 ? -sinA : sinA) * perp;
      const real along = dot(rM, w);
      const real3 off = rM - along * w;
      const real g = fmax(tube_arc_gap(s, along - R, z, r, rounding), (real)0);
      gap = fmax(gap, sqrt(g * g + dot(off, off)) - rounding * ((real)1 + R / rho));
    }
  }
  return gap - allow;
}

// A lower bound of the distance from M to patch p of a face with no exact surface, from the tube
// that holds it (docs/Solver.md, item 22; packed on the host, brt::PackPatchTube): every point of
// the patch lies within s[8] of the distance s[7] from its spine (a point, a line or a circle:
// s[9] 1, 2, 3; centre s[0..2] relative to the patch's anchor, axis s[3..5], circle radius s[6]),
// so no point of it is nearer to M than |M's distance from the spine - s[7]| - s[8]. Tight on a
// free-form round where the sphere is the round's own ball (its centre on the spine), whose
// control net's hull lets every patch of the round through. Less the rounding of M's position.
// Kind 4 (a cone's patch, or a free-form one that turns round a neighbour's axis; docs/Solver.md,
// item 23; brt::PackPatchAxisBox): the patch's part inside its trim lies within s[8] of the
// distance s[7] from the axis (through the centre s[0..2], along s[3..5]) and between the
// heights s[10] and s[11] along it; since |P - M| is at least the distance between their
// (distance from the axis, height) pairs, no point of it is nearer to M than M's pair is to that
// rectangle. Tight where the sphere's centre lies on a shaft's axis and the patch's control net,
// whose chords cut inside the circle the patch turns round, reaches into the sphere.
// Negative where the patch has no tube.
inline real tube_patch_gap(const Model* m, int p, real3 Ohi, real3 Olo, real3 mr, real t)
{
  __global const real* s = m->patchSector + PATCH_SECTOR_REALS * p;
  if (!(s[9] > (real)0))
    return (real)-1;
  const real3 X = mr - anchor_minus(m->patchAnchor + 6 * p, Ohi, Olo) - make_real3(s[0], s[1], s[2]);
  const real3 ax = make_real3(s[3], s[4], s[5]);
  const real z = dot(X, ax);
  const real rho = sqrt(fmax(dot(X, X) - z * z, (real)0));
  const real rounding = (real)64 * REAL_EPS * (length(X) + s[6] + s[7] + t);
  if (s[9] > (real)3.5)
  {
    const real dr = fmax(fabs(rho - s[7]) - s[8], (real)0);
    const real dz = z - clamp(z, s[10], s[11]);
    return sqrt(dr * dr + dz * dz) - rounding;
  }
  const real dist = s[9] < (real)1.5 ? length(X)
    : s[9] < (real)2.5              ? rho
                                    : sqrt((rho - s[6]) * (rho - s[6]) + z * z);
  return fabs(dist - s[7]) - s[8] - rounding;
}

// A lower bound of the distance from M to patch p of a spherical face, tighter than exact_gap
// where the sphere's centre lies near the ball's (a ball end, a dimple: the whole ball is then
// about its radius from M) or the ball continues beyond the patch (a corner's round). The
// patch's points lie in the cone from the ball's centre that holds its control points
// (s[8..11]: its middle direction and the cosine of its half-angle, rounded down, under a
// quarter-turn; 0 where not packed, PackDirectionCone), and each within the deviation of its foot
// on the ball, on the same ray from the centre. Where M's direction from the centre lies outside
// that cone, the nearest point of the ball's cap inside it lies on the cap's rim, in the plane of
// the cone's middle and M. Less the deviation and the rounding of M's position and direction.
// Negative: no bound.
inline real sphere_patch_gap(const Model* m, int p, int face, real3 Ohi, real3 Olo, real3 mr,
  real t)
{
  __global const real* s = m->patchSector + PATCH_SECTOR_REALS * p;
  if (!(s[11] > (real)0))
    return (real)-1;
  __global const real* e = m->faceDomain + FACE_REALS * face + FACE_EXACT;
  const real rs = e[9];
  const real3 X = mr - anchor_minus(e, Ohi, Olo); // M - the ball's centre
  const real3 mid = make_real3(s[8], s[9], s[10]);
  const real along = dot(X, mid);
  const real3 across = X - along * mid;
  const real la = length(across), lx = length(X);
  if (!(la > (real)0) || along >= s[11] * lx)
    return (real)-1;
  const real sinA = sqrt(fmax((real)1 - s[11] * s[11], (real)0));
  const real3 g = X - rs * (s[11] * mid + (sinA / la) * across);
  const real rounding = (real)8 * REAL_EPS * (lx + rs + t);
  return length(g) - rounding * ((real)1 + rs / lx) - deviation_allowance(m, face, X, t);
}

// --- a plane's trimmed face against a sphere -------------------------------------------------
// Pushes the halves of the cubic piece q (four (u, v) control points; de Casteljau at its
// middle) onto the stack st at *top, one level below `level`, the second half on top.
inline void push_halves(real2 (*st)[4], int* depthOf, int* top, const real2* q, int level)
{
  const real2 a = (real)0.5 * (q[0] + q[1]), b = (real)0.5 * (q[1] + q[2]);
  const real2 f = (real)0.5 * (q[2] + q[3]);
  const real2 ab = (real)0.5 * (a + b), bf = (real)0.5 * (b + f), mid = (real)0.5 * (ab + bf);
  const int k = *top;
  st[k][0] = q[0];
  st[k][1] = a;
  st[k][2] = ab;
  st[k][3] = mid;
  st[k + 1][0] = mid;
  st[k + 1][1] = bf;
  st[k + 1][2] = f;
  st[k + 1][3] = q[3];
  depthOf[k] = depthOf[k + 1] = level + 1;
  *top = k + 2;
}

// A cubic piece q (four (u, v) control points, both ends at least r from P) against the disk of
// radius r about P, by f(s) = |q(s) - P|^2, a polynomial of degree 6: 1 where f stays at least
// r2 = r^2 on the piece, -1 where a point of the piece lies nearer than r, 0 undecided. f lies
// above the least of its Bernstein coefficients (an arc about P: f all but constant). Where its
// second differences are all positive f is convex, so it lies above its tangents: Newton on f'
// (safeguarded by bisection) closes in on its minimum, and the two tangents at the ends of the
// bracket [lo, hi] around it (f' < 0 at lo, > 0 at hi) meet below every value of f. A curve that
// passes just outside the disk (a trim next to a fillet's edge, where the sphere meets the plane
// almost tangent to the trim) is decided so without the halvings that would narrow its box to
// the gap.
inline int piece_clear_of(const real2* q, real2 P, real r2)
{
  const real2 w0 = q[0] - P, w1 = q[1] - P, w2 = q[2] - P, w3 = q[3] - P;
  real b[7];
  b[0] = dot(w0, w0);
  b[1] = dot(w0, w1);
  b[2] = (real)0.4 * dot(w0, w2) + (real)0.6 * dot(w1, w1);
  b[3] = (real)0.1 * dot(w0, w3) + (real)0.9 * dot(w1, w2);
  b[4] = (real)0.4 * dot(w1, w3) + (real)0.6 * dot(w2, w2);
  b[5] = dot(w2, w3);
  b[6] = dot(w3, w3);
  if (fmin(fmin(b[1], b[2]), fmin(fmin(b[3], b[4]), b[5])) >= r2)
    return 1;
  for (int k = 0; k < 5; ++k)
    if (!(b[k + 2] - (real)2 * b[k + 1] + b[k] > (real)0))
      return 0;
  // Power form of q(s) - P: a0 + a1 s + a2 s^2 + a3 s^3.
  const real2 a0 = w0, a1 = (real)3 * (w1 - w0), a2 = (real)3 * (w2 - (real)2 * w1 + w0),
              a3 = w3 - (real)3 * w2 + (real)3 * w1 - w0;
  real lo = (real)0, flo = b[0], fplo = (real)2 * dot(a0, a1);
  real hi = (real)1, fhi = b[6], fphi = (real)2 * dot(w3, a1 + (real)2 * a2 + (real)3 * a3);
  // f' rises (convex f): where it does not change sign, the minimum is at an end.
  if (!(fplo < (real)0) || !(fphi > (real)0))
    return 1;
  real s = fplo / (fplo - fphi);
  for (int it = 0; it < 8; ++it)
  {
    const real2 W = a0 + s * (a1 + s * (a2 + s * a3));
    const real2 Wp = a1 + s * ((real)2 * a2 + (real)3 * s * a3);
    const real2 Wpp = (real)2 * a2 + (real)6 * s * a3;
    const real f = dot(W, W), fp = (real)2 * dot(W, Wp), fpp = (real)2 * (dot(Wp, Wp) + dot(W, Wpp));
    if (f < r2)
      return -1;
    if (fp < (real)0)
    {
      lo = s;
      flo = f;
      fplo = fp;
    }
    else
    {
      hi = s;
      fhi = f;
      fphi = fp;
    }
    // Where the tangents at lo and hi meet: below f on [lo, hi], and f rises away from it.
    const real x = (fhi - flo + fplo * lo - fphi * hi) / (fplo - fphi);
    const real low = flo + fplo * (fmin(fmax(x, lo), hi) - lo);
    if (fmin(low, fmin(flo, fhi)) >= r2)
      return 1;
    const real next = fpp > (real)0 ? s - fp / fpp : (real)-1;
    s = next > lo && next < hi ? next : (real)0.5 * (lo + hi);
  }
  return 0;
}

// 1 when the cubic trimming segment c (four (u, v) control points) lies at least r from P: each
// piece lies in the hull of its control points, so in their box along its chord and across it,
// or piece_clear_of decides it; pieces neither clears are halved (de Casteljau), up to 10
// times. 0 where a point of the curve lies nearer, or the halvings run out.
int segment_clear_of(__global const real* c, real2 P, real r)
{
  real2 st[12][4];
  int depthOf[12];
  for (int i = 0; i < 4; ++i)
    st[0][i] = make_real2(c[2 * i], c[2 * i + 1]);
  depthOf[0] = 0;
  int top = 1;
  const real r2 = r * r;
  while (top > 0)
  {
    --top;
    real2 q[4];
    for (int i = 0; i < 4; ++i)
      q[i] = st[top][i];
    const int level = depthOf[top];
    if (dot(q[0] - P, q[0] - P) < r2 || dot(q[3] - P, q[3] - P) < r2)
      return 0;
    const real2 chord = q[3] - q[0];
    const real L = length(chord);
    const real2 e = L > (real)0 ? chord / L : make_real2((real)1, (real)0);
    const real2 n = make_real2(-e.y, e.x);
    real s0 = REAL_MAX, s1 = -REAL_MAX, n0 = REAL_MAX, n1 = -REAL_MAX;
    for (int i = 0; i < 4; ++i)
    {
      const real2 w = q[i] - P;
      const real si = dot(w, e), ni = dot(w, n);
      s0 = fmin(s0, si);
      s1 = fmax(s1, si);
      n0 = fmin(n0, ni);
      n1 = fmax(n1, ni);
    }
    const real gs = fmax(fmax(s0, -s1), (real)0), gn = fmax(fmax(n0, -n1), (real)0);
    if (gs * gs + gn * gn >= r2)
      continue;
    const int k = piece_clear_of(q, P, r2);
    if (k != 0)
    {
      if (k < 0)
        return 0;
      continue;
    }
    if (level == 10 || top + 2 > 12)
      return 0;
    push_halves(st, depthOf, &top, q, level);
  }
  return 1;
}

// The parity of the crossings of the ray from P along +u with the cubic segment c (four (u, v)
// control points), or -1 undecided: pieces whose control points' v run monotone across P's v
// cross its line once, left or right of P by their box; the others, and those whose box spans
// P's u, are halved (de Casteljau), up to 12 times. P lies off the curve (trim_segment_clear), so the
// halving ends. Half-open in v, as inside_by_crossings: an end at P's v counts on the side above.
int segment_crossings(__global const real* c, real2 P)
{
  // The ray can cross only a segment whose box spans P's v and reaches past its u.
  if (c[9] > P.y || !(c[11] > P.y) || !(c[10] > P.x))
    return 0;
  real2 st[14][4];
  int depthOf[14];
  for (int i = 0; i < 4; ++i)
    st[0][i] = make_real2(c[2 * i], c[2 * i + 1]);
  depthOf[0] = 0;
  int top = 1, parity = 0;
  while (top > 0)
  {
    --top;
    real2 q[4];
    for (int i = 0; i < 4; ++i)
      q[i] = st[top][i];
    const int level = depthOf[top];
    // Which side of P's v each control point lies on (above: v > P's); the ends are the curve's.
    const int a0 = q[0].y > P.y, a1 = q[1].y > P.y, a2 = q[2].y > P.y, a3 = q[3].y > P.y;
    if (a0 == a1 && a1 == a2 && a2 == a3)
      continue; // the piece stays on one side: no crossing
    const real lu = fmin(fmin(q[0].x, q[1].x), fmin(q[2].x, q[3].x));
    const real hu = fmax(fmax(q[0].x, q[1].x), fmax(q[2].x, q[3].x));
    if (!(hu > P.x))
      continue; // wholly left of P
    // Monotone in v (the control points' v in order): the curve crosses P's line exactly as
    // often as its ends differ in side, once.
    const int monotone = (q[0].y <= q[1].y && q[1].y <= q[2].y && q[2].y <= q[3].y) ||
      (q[0].y >= q[1].y && q[1].y >= q[2].y && q[2].y >= q[3].y);
    if (monotone && lu > P.x)
    {
      parity ^= a0 != a3;
      continue;
    }
    if (level == 12 || top + 2 > 14)
      return -1;
    push_halves(st, depthOf, &top, q, level);
  }
  return parity;
}

// One trimming segment c for trim_side_if_clear: 0 where it comes within r of P
// (segment_clear_of), -1 where its crossings are undecided, else 1 with their parity added to
// *parity.
inline int trim_segment_clear(__global const real* c, real2 P, real r, int* parity)
{
  if (box_distance2(c, P) < r * r && !segment_clear_of(c, P, r))
    return 0;
  const int k = segment_crossings(c, P);
  if (k < 0)
    return -1;
  *parity ^= k & 1;
  return 1;
}

// Where no trimming segment of `face` comes within r of P in (u, v), which side of the trim P
// lies on, by the parity of the segments' crossings with the ray from P along +u: 1 outside, 2
// inside; 0 where a segment comes within r, -1 where a crossing is undecided. One walk of the
// face's segment tree where it has one, over the nodes near P or across the ray.
int trim_side_if_clear(const Model* m, int face, real2 P, real r)
{
  __global const int* fi = m->faceInfo + FACE_INTS * face;
  int parity = 0;
  if (fi[9] >= 0)
  {
    int stack[32];
    int top = 0;
    stack[top++] = fi[9];
    while (top > 0)
    {
      const int n = stack[--top];
      __global const real* b = m->trimNodeBox + 4 * n;
      const int across = !(b[1] > P.y) && b[3] > P.y && b[2] > P.x;
      if (!across && !(uv_box_gap2(b, P) < r * r))
        continue;
      __global const int* ni = m->trimNodeInfo + 3 * n;
      if (ni[1] > 0)
      {
        for (int j = 0; j < ni[1]; ++j)
        {
          const int k = trim_segment_clear(m->trim + TRIM_REALS * m->trimItems[2 * (ni[0] + j)],
            P, r, &parity);
          if (k <= 0)
            return k;
        }
        continue;
      }
      if (top + 2 > 32)
        return -1; // never: the tree is balanced
      stack[top++] = ni[2];
      stack[top++] = n + 1;
    }
    return 1 + parity;
  }
  for (int l = fi[4]; l < fi[4] + fi[5]; ++l)
  {
    const int first = m->loops[2 * l], count = m->loops[2 * l + 1];
    for (int s = first; s < first + count; ++s)
    {
      const int k = trim_segment_clear(m->trim + TRIM_REALS * s, P, r, &parity);
      if (k <= 0)
        return k;
    }
  }
  return 1 + parity;
}

// A lower bound of the distance from the centre M (O + mr) to a plane `face` whose patches are
// its isometric parametrisation (FACE_INTS slot 11), given gap, the plane's own bound (exact_gap),
// and need, the distance below which a point would count: where M's foot on the plane lies
// outside the trim and no trimming curve comes within rho of it, rho the radius of the disk in
// which the sphere of radius need (and the patches' deviation) meets the plane, no point of the
// face lies in that disk, and the face is at least sqrt(h^2 + rho^2) from M, h M's height over
// the plane. A plane's patches cover its whole (u, v) box, holes included: a sphere that crosses
// the plane inside a hole reached its patches there, and each was searched (certify_patch) to find
// its nearest point off the face (the engine block's mold model, a finned casting, +12%;
// docs/Solver.md, item 13, "A plane's hole").
real plane_trim_gap(const Model* m, int face, real3 Ohi, real3 Olo, real3 mr, real t, real gap,
  real need)
{
  __global const int* fi = m->faceInfo + FACE_INTS * face;
  real3 X, Y;
  if (!(gap < need) || !plane_face_frame(m, face, &X, &Y))
    return gap;
  __global const real* fd = m->faceDomain + FACE_REALS * face;
  __global const real* e = fd + FACE_EXACT;
  const real3 a = make_real3(e[6], e[7], e[8]);
  const real3 XM = mr - anchor_minus(e, Ohi, Olo);
  const real h = fabs(dot(XM, a));
  // The plane's origin is its first patch's first control point, at that patch's (u0, v0).
  __global const real* pd = m->patchDomain + 4 * fi[0];
  const real2 P = make_real2(pd[0] + dot(XM, X), pd[2] + dot(XM, Y));
  const real allow = deviation_allowance(m, face, XM, t);
  // The disk of a reach some roundings wider than the need's, so that the bound it proves
  // clears the need itself: from the need's own disk the root below gave the need less an ulp
  // (on 254 of 400 of NIST_MBE_PMI_11's plane patches searched for nothing, each a patch search
  // of about 10k instructions for a face this proved clear). A quarter of that room is given up
  // again for the root's rounding.
  const real room = (real)32 * REAL_EPS * (need + allow + h);
  const real reach = need + allow + room;
  // The margin: points within 1e-9 of the domain's size of the trim count as on it
  // (consider_point), and P's rounding.
  const real size = fd[1] - fd[0] + fd[3] - fd[2];
#ifdef BRT_DOUBLE
  const real margin = (real)1e-9 * size + (real)64 * REAL_EPS * (length(XM) + t);
#else
  const real margin = (real)1e-9 * size + (real)16 * FLT_EPSILON * (length(XM) + t + size);
#endif
  const real rho = sqrt(fmax(reach * reach - h * h, (real)0)) + margin;
  if (trim_side_if_clear(m, face, P, rho) != 1)
    return gap;
  const real clear = rho - margin;
  return fmax(gap, sqrt(h * h + clear * clear) - allow - (real)0.25 * room);
}

// The certification of the sphere of radius t tangent at O: the deepest
// point of the trimmed faces of O's solid more than `depth` inside it (by more than half the
// conversion tolerance, above the Newton solves' error at the contact). Every patch and edge
// segment whose control-point box reaches into the sphere is searched. 0 where none is that
// deep: the sphere is empty up to the depth, at the patches' accuracy.
BRT_SPLIT int find_point_inside(const Model* m, int ownFace, real3 Ohi, real3 Olo, real3 d, real t,
  real depth, PointInside* st)
{
  st->found = 0;
  st->edge = -1;
  st->onTrim = 0;
  st->trimFace = -1;
  const real reach = t - depth - (real)0.25 * m->slack;
  if (!(m->mode & MODE_CERTIFY) || !(reach > (real)0))
    return 0;
  const int solid = scope_solid(m, ownFace);
  const real3 mr = t * d;               // M - O
  const real3 M = Ohi + Olo + mr;       // M relative to the model's centre, for the boxes
  st->best = reach;
  // Each entry keeps its box's squared gap from M (M does not move during the query; only the
  // best distance shrinks): tested again when popped, without computing it twice. The tree is
  // balanced (median splits), so 32 entries hold a walk over up to 2^31 leaves.
  int stack[32];
  real stackGap[32];
  int top = 0;
  stack[top] = 0;
  stackGap[top++] = box_gap2(m->boxNodeBox, M);
  // exact_gap depends on the face alone (M and t do not change during the query): kept for the
  // last face asked, which a leaf's patches mostly share.
  int gapFace = -1, nodeGapFace = -1;
  real gapOfFace = (real)0, nodeGap = (real)0;
  // The need's caps on O's own face and its edges (below), and the best distance squared, kept
  // with st->best (only the searches change it).
  const real ownCap = ownFace >= 0 ? reach - own_face_margin_near(m, ownFace) : reach;
  const real ownEdgeCap = reach - m->slack;
  real best2 = st->best * st->best;
  while (top > 0)
  {
    --top;
    const int node = stack[top];
    if (stackGap[top] >= best2)
      continue;
    __global const int* ni = m->boxNodeInfo + 3 * node;
    // An inner node whose subtree lies on one solid has Count = -(solid + 1) (BuildPatchBoxes):
    // another solid's subtree holds nothing in scope.
    if (ni[1] < 0 && solid >= 0 && -ni[1] - 1 != solid)
      continue;
    // An inner node whose items are all patches of one face has that face as First (else -1;
    // BuildPatchBoxes). Where the face's exact surface lies farther from M than the need its
    // patches would be asked (exact_gap), each of them would be passed over below (the leaves'
    // bound is at least that: plane_trim_gap only raises it), so the subtree is skipped whole:
    // a torus sample's own face had 23 of its 26 patches past their boxes on NIST_MBE_PMI_11.
    // Its own one-face memory (exact_gap does not depend on the need), so that the leaves'
    // (gapFace) holds what it held before.
    if (ni[1] <= 0 && ni[0] >= 0)
    {
      const int face = ni[0];
      const real need = face == ownFace ? fmin(st->best, ownCap) : st->best;
      if (face != nodeGapFace)
      {
        nodeGapFace = face;
        nodeGap = exact_gap(m, face, Ohi, Olo, mr, t);
      }
      if (!(nodeGap < need))
        continue;
    }
    if (ni[1] > 0)
    {
      for (int i = ni[0]; i < ni[0] + ni[1]; ++i)
      {
        // A piece is searched only where its bounds leave room for a point that would count
        // (consider_point, certify_edge): nearer to M than the best so far (on O's own face,
        // also a slack deeper than the reach) and in front of O by more than the depth (the
        // control points' farthest offset along d bounds the piece's).
        const int item = m->boxItems[i];
        if (item < m->patchCount)
        {
          const int face = m->patchFace[item];
          const real need = face == ownFace ? fmin(st->best, ownCap) : st->best;
          if (!in_scope(m->faceInfo, face, solid) ||
            !(box_gap2(m->patchBoxes + 6 * item, M) < need * need))
            continue;
          if (face != gapFace)
          {
            gapFace = face;
            gapOfFace = plane_trim_gap(m, face, Ohi, Olo, mr, t,
              exact_gap(m, face, Ohi, Olo, mr, t), need);
          }
          // The piece's bound of a cylinder, torus or sphere before the control net's: of the
          // curved patches whose face's bound let them through, it clears 89-98% on the four
          // Data/ parts (18-67% on NIST_MBE_PMI_1 and _3), and on all six every one the net's
          // clears (counted in a throwaway build; docs/Solver.md).
          real ahead;
          const int kind = m->faceInfo[FACE_INTS * face + 8];
          if (gapOfFace < need &&
            (kind != EXACT_CYLINDER || cylinder_patch_gap(m, item, face, Ohi, Olo, mr, t, need) < need) &&
            (kind != EXACT_TORUS || torus_patch_gap(m, item, face, Ohi, Olo, mr, t, need) < need) &&
            (kind != EXACT_SPHERE || sphere_patch_gap(m, item, face, Ohi, Olo, mr, t) < need) &&
            ((kind != EXACT_NONE && kind != EXACT_CONE) ||
              tube_patch_gap(m, item, Ohi, Olo, mr, t) < need) &&
            patch_gap(m, item, anchor_minus(m->patchAnchor + 6 * item, Ohi, Olo) - mr, mr, d,
              &ahead) < need &&
            ahead > depth)
          {
            certify_patch(m, item, ownFace, Ohi, Olo, d, mr, depth, reach, st);
            best2 = st->best * st->best;
          }
        }
        else
        {
          const int es = item - m->patchCount;
          const int edge = m->edgeSegEdge[es];
          const int f0 = m->edgeInfo[4 * edge + 2], f1 = m->edgeInfo[4 * edge + 3];
          const real need = f0 == ownFace || f1 == ownFace ? fmin(st->best, ownEdgeCap) : st->best;
          if (!(f0 >= 0 && in_scope(m->faceInfo, f0, solid) &&
                box_gap2(m->edgeBoxes + 6 * es, M) < need * need))
            continue;
          // The edge lies within its measured distance of each face's exact surface: no point of
          // it is nearer to M than M's distance from that surface, less that.
          real edgeGap = (real)-1;
          for (int k = 0; k < 2; ++k)
          {
            const int f = k ? f1 : f0;
            const real dev = m->edgeRange[4 * edge + 2 + k];
            const int kind = f >= 0 ? m->faceInfo[FACE_INTS * f + 8] : EXACT_NONE;
            if (kind == EXACT_NONE || !(dev >= (real)0))
              continue;
            __global const real* e = m->faceDomain + FACE_REALS * f + FACE_EXACT;
            const real3 X = mr - anchor_minus(e, Ohi, Olo);
#ifdef BRT_DOUBLE
            const real allow = dev + (real)64 * REAL_EPS * (length(X) + t);
#else
            const real allow = fmax(dev, (real)0.5 * m->slack);
#endif
            edgeGap = fmax(edgeGap, exact_bound_distance(kind, e, X) - allow);
          }
          __global const real* c = m->edgeSeg + 12 * es;
          const real3 a = anchor_minus(m->edgeAnchor + 6 * es, Ohi, Olo);
          if (edgeGap < need && -hull_gap(c, 4, a, -d) > depth &&
            hull_gap(c, 4, a - mr, toward_hull(c, 4, a - mr)) < need)
          {
            certify_edge(m, es, ownFace, Ohi, Olo, d, mr, depth, reach, st);
            best2 = st->best * st->best;
          }
        }
      }
      continue;
    }
    if (top + 2 > 32)
      continue; // cannot happen for a balanced tree
    const int left = node + 1, right = ni[2];
    const real gl = box_gap2(m->boxNodeBox + 6 * left, M), gr = box_gap2(m->boxNodeBox + 6 * right, M);
    const int leftFirst = gl <= gr;
    stack[top] = leftFirst ? right : left;
    stackGap[top++] = leftFirst ? gr : gl;
    stack[top] = leftFirst ? left : right;
    stackGap[top++] = leftFirst ? gl : gr;
  }
  return st->found;
}

// --- the exact finish -------------------------------------------------------------------------
// The patches approximate an analytic face within the conversion tolerance; a contact found on
// them is moved onto the face's exact surface (plane, cylinder, cone, sphere, torus), so that
// the closed forms hold at the reader's default tolerance (docs/Solver.md, "Exact finish").

// Two faces lie on one exact surface (a seam's face with itself, a cylinder split in halves).
inline int same_exact_surface(const Model* m, int f0, int f1)
{
  if (f0 < 0 || f1 < 0)
    return 0;
  if (f0 == f1)
    return 1;
  const int kind = m->faceInfo[FACE_INTS * f0 + 8];
  if (kind == EXACT_NONE || kind != m->faceInfo[FACE_INTS * f1 + 8])
    return 0;
  __global const real* a = m->faceDomain + FACE_REALS * f0 + FACE_EXACT;
  __global const real* b = m->faceDomain + FACE_REALS * f1 + FACE_EXACT;
  // The origins may differ along the axis (or in the plane): compare the surfaces themselves.
  const real3 oa = make_real3(a[0], a[1], a[2]) + make_real3(a[3], a[4], a[5]);
  const real3 ob = make_real3(b[0], b[1], b[2]) + make_real3(b[3], b[4], b[5]);
  const real3 ax = make_real3(a[6], a[7], a[8]), bx = make_real3(b[6], b[7], b[8]);
  const real tol = (real)1e-3 * m->slack;
  if (length(cross(ax, bx)) > (real)1e-9)
    return 0;
  const real3 w = ob - oa;
  if (kind == EXACT_PLANE)
    return fabs(dot(w, ax)) <= tol;
  if (kind == EXACT_SPHERE || kind == EXACT_TORUS)
    return length(w) <= tol && fabs(a[9] - b[9]) <= tol && fabs(a[10] - b[10]) <= tol;
  // Cylinder, cone: one axis line, and for the cone the same radius at the same height.
  const real along = dot(w, ax);
  if (length(w - along * ax) > tol)
    return 0;
  if (kind == EXACT_CYLINDER)
    return fabs(a[9] - b[9]) <= tol;
  return fabs(a[10] - b[10]) <= (real)1e-9 && fabs(a[11] - b[11]) <= (real)1e-9 &&
    fabs(a[9] + along * a[11] / a[10] - b[9]) <= tol;
}

// O on a cylinder, cone, sphere or torus (X0 = O - its origin), d its inward normal: the sphere
// that touches that surface across, through its axis, centre or core circle (a rod, a tapered
// rod, a ball, a ring; on a cone the centre is where the normal line meets the axis).
// |dist(O + t d)| = t holds for every t up to that sphere's radius (O is the nearest point), so
// Newton on the exact surface cannot find it; this is its closed form: t where O + t d comes
// nearest to the axis or centre (the torus: the distance to the core circle). 0 where O is not on
// the surface (within slack) or d not its inward normal.
int self_contact_radius(int kind, __global const real* e, real3 X0, real3 d, real slack, real* t)
{
  if (kind != EXACT_CYLINDER && kind != EXACT_CONE && kind != EXACT_SPHERE && kind != EXACT_TORUS)
    return 0;
  real3 g;
  int ok;
  const real f = exact_distance(kind, e, X0, &g, &ok);
  if (!ok || !(fabs(f) <= slack) || !(dot(g, d) < (real)-0.999))
    return 0;
  if (kind == EXACT_TORUS)
    *t = e[10] + f;
  else
  {
    const real3 a = make_real3(e[6], e[7], e[8]);
    const real3 Xp = kind == EXACT_SPHERE ? X0 : X0 - dot(X0, a) * a;
    const real3 dp = kind == EXACT_SPHERE ? d : d - dot(d, a) * a;
    const real dd = dot(dp, dp);
    if (!(dd > (real)0.5))
      return 0;
    *t = -dot(Xp, dp) / dd;
  }
  return *t > (real)0;
}

// The sphere of radius t tangent at O to its own cylinder, cone, sphere or torus and touching it
// across (self_contact_radius; X0 = O - the surface's origin): it touches the surface along a
// circle (a ball: everywhere). Its foot (relative to O) nearest `near` (relative to O, a point
// next to that circle), in *foot; 0 where `near` lies too close to the sphere's centre or axis
// to say.
int self_contact_foot(int kind, __global const real* e, real3 X0, real3 d, real t, real3 near,
  real3* foot)
{
  const real3 a = make_real3(e[6], e[7], e[8]);
  if (kind == EXACT_CONE)
  {
    // The circle through O around the axis, at O's height: the foot is its point in the
    // direction of `near` around the axis.
    const real3 rel = -t * d; // O - the centre
    const real za = dot(rel, a);
    const real3 r0 = rel - za * a;
    const real rho = length(r0);
    real3 w = near - t * d;
    w = w - dot(w, a) * a;
    const real lw = length(w);
    if (!(t > (real)0) || !(rho > (real)0) || !(lw > (real)0.5 * rho))
      return 0;
    w = w / lw;
#ifndef BRT_DOUBLE
    // In float, not within 60 degrees of O around the axis (as below).
    const real3 w0 = r0 / rho;
    const real c = dot(w, w0);
    if (c > (real)0.5)
    {
      const real3 side = w - c * w0;
      const real ls = length(side);
      if (!(ls > (real)1e-3))
        return 0;
      w = (real)0.8660254037844386 * (side / ls) + (real)0.5 * w0;
    }
#endif
    *foot = t * d + za * a + rho * w;
    return 1;
  }
  real3 across = near - t * d; // from the centre towards `near`
  if (kind == EXACT_CYLINDER)
    across = across - dot(across, a) * a;
  else if (kind == EXACT_TORUS)
  {
    // In the meridian plane of the centre: without the core circle's tangent.
    const real3 C = X0 + t * d;
    const real3 tangent = normalize(cross(a, C - dot(C, a) * a));
    across = across - dot(across, tangent) * tangent;
  }
  const real la = length(across);
  if (!(t > (real)0) || !(la > (real)0.5 * t))
    return 0;
#ifndef BRT_DOUBLE
  // In float, not within 60 degrees of O around the centre: a foot next to O (a start or a
  // chain's hint next to O gives one) makes the radius through it, sphere_radius in
  // write_result, lose the digits of |foot|^2 / 2 d.foot (the float kernel without the finish
  // read the rod split in halves 1.2e-5 off with chains of 32). The point 60 degrees from O
  // towards `near` instead, on the same circle (|foot| = t there). In double the rounding is
  // harmless, and the foot next to the start stays (every other foot moves the chain's next
  // starts, and with them 699 of 7 million spheres by 1e-6 to 2.5e-4 relative, for better and
  // for worse: docs/Solver.md, item 20).
  const real toO = -dot(across, d) / la;
  if (toO > (real)0.5)
  {
    const real3 side = across + (toO * la) * d; // across without its part towards O
    const real ls = length(side);
    if (!(ls > (real)1e-3 * t))
      return 0;
    across = (real)0.8660254037844386 * la * (side / ls) - (real)0.5 * la * d;
  }
#endif
  *foot = t * d + across * (t / la);
  return 1;
}

// One Gauss-Newton step on |S(u, v) - target|^2 over `face`'s patches (target relative to O),
// from (u, v) on *patch: (u, v) moved, wrapped and clamped to the face's bounds, *patch the patch
// there. Returns the step's size |du| + |dv|; 0 (no step) where S(u, v) lies within `within` of
// the target already (also where the parametrisation degenerates: a sphere's pole); -1 where the
// step is not defined.
real face_gauss_newton_step(const Model* m, int face, real3 Ohi, real3 Olo, real3 target,
  real within, real* u, real* v, int* patch)
{
  __global const real* fd = m->faceDomain + FACE_REALS * face;
  const PatchEval pe = eval_patch(m, *patch, *u, *v);
  const real3 q = pe.P + anchor_minus(m->patchAnchor + 6 * *patch, Ohi, Olo) - target;
  if (length(q) <= within)
    return (real)0;
  const real a = dot(pe.Du, pe.Du), b = dot(pe.Du, pe.Dv), c = dot(pe.Dv, pe.Dv);
  const real det = a * c - b * b;
  if (!(det > (real)0))
    return (real)-1;
  const real gu = dot(pe.Du, q), gv = dot(pe.Dv, q);
  const real du = -(c * gu - b * gv) / det, dv = -(a * gv - b * gu) / det;
  *u += du;
  *v += dv;
  if (fd[4] > (real)0)
    *u = wrap_param(*u, fd[0], fd[4]);
  if (fd[5] > (real)0)
    *v = wrap_param(*v, fd[2], fd[5]);
  *u = clamp(*u, fd[0], fd[1]);
  *v = clamp(*v, fd[2], fd[3]);
  *patch = find_patch(m, face, *u, *v);
  return fabs(du) + fabs(dv);
}

// The face across the edge of trimming segment seg (at its parameter param) tangent there to a
// sphere of centre c (relative to O), within 1e-3 rad: the edge is a tangent edge where the sphere
// touches it, so a foot in the trim's tolerance band of that edge is the contact of the faces
// either side (a plate's face where its round begins). Next to a convex edge the face across meets
// such a sphere at an angle, and the band does not count (docs/Solver.md, "Exact finish").
int tangent_across(const Model* m, int face, int seg, real param, real3 Ohi, real3 Olo, real3 c)
{
  if (seg < 0)
    return 0;
  const int edge = m->trimEdge[seg];
  if (edge < 0 || m->edgeInfo[4 * edge + 1] == 0)
    return 0;
  const int f0 = m->edgeInfo[4 * edge + 2], f1 = m->edgeInfo[4 * edge + 3];
  const int other = f0 == face ? f1 : (f1 == face ? f0 : -1);
  if (other < 0 || other == face)
    return 0;
  const real T = m->trimRange[2 * seg] + param * (m->trimRange[2 * seg + 1] - m->trimRange[2 * seg]);
  real u, v;
  if (!edge_point_on_face(m, other, edge, T, &u, &v))
    return 0;
  real3 C, Ct, Ctt;
  eval_edge(m, edge, T, Ohi, Olo, &C, &Ct, &Ctt);
  const PatchEval e = eval_patch(m, find_patch(m, other, u, v), u, v);
  const real3 n = cross(e.Du, e.Dv), q = C - c;
  const real ln = length(n), lq = length(q);
  return ln > (real)0 && lq > (real)0 && length(cross(n, q)) <= (real)1e-3 * ln * lq;
}

// `foot` (relative to O) projected onto `face`'s patches from (u, v): Gauss-Newton on
// |S(u, v) - foot|^2. 1 when it reaches the foot (within the slack) inside the face's trim, with
// its (u, v) and patch. Within the trim's tolerance band of an edge too: with band 1 anywhere,
// with band 2 where the face across is tangent there to the sphere of centre `centre` (relative
// to O; tangent_across); band 0, strictly inside only. Where the trim test is known to put every
// point within insideRadius of insideUV (in UV) on the face, a point reached within that disk
// needs no test of its own (the disk holds no trimming curve); insideRadius 0: no such disk.
BRT_SPLIT int project_on_face_near(const Model* m, int face, real3 Ohi, real3 Olo, real3 foot, int band,
  real3 centre, real2 insideUV, real insideRadius, real* uio, real* vio, int* patchOut)
{
  real u = *uio, v = *vio;
  __global const real* fd = m->faceDomain + FACE_REALS * face;
  int patch = find_patch(m, face, u, v);
  for (int it = 0; it < 6; ++it)
  {
    const real step =
      face_gauss_newton_step(m, face, Ohi, Olo, foot, (real)0.01 * m->slack, &u, &v, &patch);
    if (step < (real)0)
      return 0;
    if (step <= (real)1e-9 * (fd[1] - fd[0] + fd[3] - fd[2]))
      break;
  }
  // Converged onto the foot (the patches lie within slack / 2 of the surface it is on).
  const PatchEval pe = eval_patch(m, patch, u, v);
  if (!(length(pe.P + anchor_minus(m->patchAnchor + 6 * patch, Ohi, Olo) - foot) <= m->slack))
    return 0;
  if (!(length(make_real2(u, v) - insideUV) < insideRadius))
  {
    int seg;
    real param, trimDist;
    const int inside = classify(m, face, make_real2(u, v), &seg, &param, &trimDist);
    if (!inside && !(band && trimDist <= fd[6] &&
                     (band == 1 || tangent_across(m, face, seg, param, Ohi, Olo, centre))))
      return 0;
  }
  *uio = u;
  *vio = v;
  *patchOut = patch;
  return 1;
}

// The same without a known disk.
int project_on_face(const Model* m, int face, real3 Ohi, real3 Olo, real3 foot, int band, real* uio,
  real* vio, int* patchOut)
{
  return project_on_face_near(m, face, Ohi, Olo, foot, band, splat_real3(0), splat_real2(0),
    (real)0, uio, vio, patchOut);
}

// The sphere tangent at O of a surface/surface contact on an analytic face (or a surface/edge
// contact on a seam or split line, then reported as surface/surface), made tangent to the exact
// surface: Newton on g(t) = |dist(O + t d)| - t from the patches' radius, the foot the nearest
// point of the exact surface to the centre. Kept only where the sphere is more than twice the
// patches' accuracy, its centre clearly on its own side of the face, Newton converges, the
// sphere grows by at most what the patches' accuracy moves it (certified again past half the
// slack), the foot moves by at most twice the patches' accuracy (5% of t along a seam) and stays
// inside the face's trim (in its tolerance band only at a tangent edge, tangent_across); else r
// is left as it is. A
// sphere touching O's own cylinder, cone, sphere or torus across takes self_contact_radius's closed
// form instead of the Newton.
BRT_SPLIT void exact_finish(const Model* m, int ownFace, real3 Ohi, real3 Olo, real3 d, real stepTol,
  Result* r)
{
  int face = r->face;
  if (r->type == CONTACT_SURFACE_EDGE && r->edge >= 0)
  {
    // An edge within one smooth exact surface (a seam, the line where a split cylinder's halves
    // meet) is no feature: the contact is with the surface.
    const int f0 = m->edgeInfo[4 * r->edge + 2], f1 = m->edgeInfo[4 * r->edge + 3];
    face = same_exact_surface(m, f0, f1) ? f0 : -1;
  }
  else if (r->type != CONTACT_SURFACE_SURFACE)
    return;
  if (face < 0)
    return;
  const int kind = m->faceInfo[FACE_INTS * face + 8];
  if (kind == EXACT_NONE)
    return;
  __global const real* e = m->faceDomain + FACE_REALS * face + FACE_EXACT;
  const real3 X0 = -anchor_minus(e, Ohi, Olo); // O - origin
  real t = sphere_radius(d, r->foot, (real)0);
  // Spheres of a few clearances (next to a convex edge, where the clearance chose the foot and
  // the sphere may touch the face across from outside) keep the patches' contact.
  if (!(t > (real)2 * m->slack))
    return;
  if (r->type == CONTACT_SURFACE_SURFACE)
  {
    // The centre on the sphere's side of the face (material for thickness, air for the gap),
    // clearly: the patch's outward normal at the foot against the centre's direction.
    const int p0 = r->patch >= 0 ? r->patch : find_patch(m, face, r->param.x, r->param.y);
    const PatchEval pe = eval_patch(m, p0, r->param.x, r->param.y);
    real3 n = cross(pe.Du, pe.Dv);
    const real ln = length(n);
    if (!(ln > (real)0))
      return;
    n = n / ln * (m->faceInfo[FACE_INTS * face + 6] ? (real)-1 : (real)1);
    const real side = dot(t * d - r->foot, n) * ((m->mode & MODE_EXTERIOR) ? (real)-1 : (real)1);
    if (!(side < (real)-0.5 * t))
      return;
  }
  real3 g;
  int ok;
  real3 foot;
  real f;
  real tSelf;
  const int selfContact = self_contact_radius(kind, e, X0, d, m->slack, &tSelf);
  if (selfContact)
  {
    // O lies on the contact's own surface, d along its inward normal: a rod, a ball or a ring,
    // the sphere touching the surface across; the foot the surface point across from the
    // patches' foot.
    t = tSelf;
    if (!self_contact_foot(kind, e, X0, d, t, r->foot, &foot))
      return;
  }
  else
  {
    // Towards the patches' foot where the centre lies on the axis.
    f = exact_distance_towards(kind, e, X0 + t * d, r->foot - t * d, &g, &ok);
    const real sigma = f < (real)0 ? (real)-1 : (real)1;
    int converged = 0;
    for (int it = 0; it < 8 && ok; ++it)
    {
      const real slope = sigma * dot(g, d) - (real)1;
      if (!(slope < (real)-1e-3))
        return; // the foot next to O's direction: ill-conditioned
      const real step = (sigma * f - t) / slope;
      t -= step;
      f = exact_distance_towards(kind, e, X0 + t * d, r->foot - t * d, &g, &ok);
      if (fabs(step) <= stepTol)
      {
        converged = 1;
        break;
      }
    }
    if (!converged || !ok || !(t > (real)0))
      return;
    foot = t * d - f * g;
  }
  const real3 moved = foot - r->foot;
  // The patches lie within the tolerance (slack / 2) of the surface: a sphere that grows by more
  // is not the same contact. The foot may slide further: along the surface the distance from the
  // centre is flat to second order (t + s^2 / 2t on a plane or a cone's generator), so the
  // patches' error e (up to half the slack) moves the foot by up to about sqrt(4 e t), far more
  // than e on a small sphere; and one found on a seam slides along the smooth surface. Up to 5%
  // of t, or twice sqrt(slack t), or twice the slack, it is the same contact: the new foot must
  // still lie inside the face's trim (below; in its band at a tangent edge), and a sphere that
  // shrinks lies inside the one certified. A sphere that shrinks by more than the slack is no
  // longer the patches' contact made exact: next to a convex edge, where the face across meets
  // the sphere at a grazing angle, the clearance's sphere (which may hold that face up to the
  // clearance deep, step 0) is much larger than the strict one, and the clearance's stays.
  // The sphere may grow by what the patches' error moves it: the surface moved by e along its
  // normal n at the foot moves the tangent sphere by e / (1 - d.n), n towards the centre (half
  // of e for a wall straight across, more as the foot comes round towards O's tangent plane; a
  // cone's wall at 46 degrees on a Voron part read 2t 2.7e-4 short with half the slack alone).
  // Up to 64 times, and a sphere grown past half the slack is certified again, strictly
  // (below). Not a sphere touching O's own surface across (the closed form): there the growth
  // is the trim's, the sphere next to the face's edge (the mold's torus, 2t = 1 against the
  // exact 0.99964, a face across its edge 3e-5 inside the sphere).
  const real reach =
    fmax(fmax((real)2 * m->slack, (real)0.05 * t), (real)2 * sqrt(m->slack * t));
  const real tPatches = sphere_radius(d, r->foot, (real)0);
  const real across = (real)1 - dot(d, t * d - foot) / t;
  const real grow = selfContact ? (real)0
                                : (real)0.5 * m->slack *
      ((real)64 * across >= (real)1 ? (real)1 / across : (real)64);
  if (!(length(moved) <= reach) || !(t <= tPatches + fmax(grow, (real)0.5 * m->slack)) ||
    !(t >= tPatches - m->slack))
    return;
  // The new foot's (u, v): projected onto the face's patches from the old foot's (Gauss-Newton on
  // |S(u, v) - foot|^2). It must lie inside the face's trim: beyond it the surface continued
  // past the face (a round's cylinder beyond its edge) would make the sphere too small.
  real u = r->param.x, v = r->param.y;
  if (r->type == CONTACT_SURFACE_EDGE && !edge_point_on_face(m, face, r->edge, r->param.x, &u, &v))
    return;
  int patch;
  // Strictly inside for a face contact: a foot within the trim's tolerance band of an edge, where
  // the sphere may touch the edge rather than the surface, keeps the patches' contact, unless the
  // face across that edge is tangent to the sphere there (tangent_across). A seam's or
  // split line's foot lies on the same surface either side: the band counts, as it does for a
  // sphere touching its own closed surface across (its foot may fall on the surface's seam).
  // A face contact whose foot moves by less than half a hundredth of the slack (a plane's: its
  // patches lie on it to rounding) keeps its (u, v), where the projection would stop at once, and
  // the surface Newton's trim test there answers for the projection's, which is the same test.
  if (r->type == CONTACT_SURFACE_SURFACE && !selfContact &&
    length(moved) <= (real)0.005 * m->slack && r->trimSeg != -2 && r->trimUV.x == u &&
    r->trimUV.y == v)
  {
    if (!r->trimInside &&
      !(r->trimDist <= m->faceDomain[FACE_REALS * face + 6] &&
        tangent_across(m, face, r->trimSeg, r->trimParam, Ohi, Olo, t * d)))
      return;
    patch = find_patch(m, face, u, v);
  }
  else
  {
    // A face contact's own trim test (inside, this far from the trim in UV) covers the disk around
    // its (u, v) up to that distance (a thousandth less, for rounding).
    const int known = r->type == CONTACT_SURFACE_SURFACE && r->trimSeg != -2 && r->trimInside &&
      r->trimUV.x == u && r->trimUV.y == v;
    if (!project_on_face_near(m, face, Ohi, Olo, foot,
          r->type == CONTACT_SURFACE_EDGE || selfContact ? 1 : 2, t * d, make_real2(u, v),
          known ? (real)0.999 * r->trimDist : (real)0, &u, &v, &patch))
      return;
  }
  if (t > tPatches + (real)0.5 * m->slack)
  {
    // Grown past half the slack: the foot at least 4 slack inside the face's trim (in UV times
    // the metric's smallest stretch), since a face across an edge next to the foot reaches into
    // the larger sphere within the patches' error, where no certification can see it (the
    // FRAMEWORK tile's cylinder, a foot 6e-5 from its edge, read 2t 2.6e-4 above the exact on
    // 12 samples); and no point of the trimmed faces inside, strictly.
    int seg;
    real param, trimDist;
    const PatchEval pe = eval_patch(m, patch, u, v);
    const real E = dot(pe.Du, pe.Du), F = dot(pe.Du, pe.Dv), G = dot(pe.Dv, pe.Dv);
    const real stretch =
      sqrt(fmax((real)0.5 * (E + G) - sqrt((real)0.25 * (E - G) * (E - G) + F * F), (real)0));
    PointInside inside;
    if (!classify(m, face, make_real2(u, v), &seg, &param, &trimDist) ||
      !(trimDist * stretch >= (real)4 * m->slack) ||
      find_point_inside(m, ownFace, Ohi, Olo, d, t, (real)0, &inside))
      return;
  }
  if (r->type == CONTACT_SURFACE_EDGE)
  {
    r->type = CONTACT_SURFACE_SURFACE;
    r->face = face;
    r->edge = -1;
  }
  r->patch = patch;
  r->param = make_real2(u, v);
  r->foot = foot;
  r->t = t;
}

// The ray's hit at distance s on an analytic face, moved onto its exact surface (Newton on the
// signed distance along the ray), where the patches' hit lies within their accuracy of that
// surface. Along a ray that meets the surface at a small angle the hit moves by that distance
// over the angle's sine.
real exact_ray_hit(const Model* m, int face, real3 Ohi, real3 Olo, real3 d, real s, real stepTol)
{
  const int kind = m->faceInfo[FACE_INTS * face + 8];
  if (kind == EXACT_NONE)
    return s;
  __global const real* e = m->faceDomain + FACE_REALS * face + FACE_EXACT;
  const real3 X0 = -anchor_minus(e, Ohi, Olo);
  real x = s;
  for (int it = 0; it < 8; ++it)
  {
    real3 g;
    int ok;
    const real f = exact_distance(kind, e, X0 + x * d, &g, &ok);
    if (it == 0 && !(fabs(f) <= m->slack))
      return s;
    const real slope = dot(g, d);
    if (!ok || !(fabs(slope) > (real)1e-3))
      return s; // grazing
    const real step = f / slope;
    x -= step;
    if (fabs(step) <= stepTol)
      return x > (real)0 ? x : s;
  }
  return s;
}

// --- ray thickness (issue 14) --------------------------------------------------------------
// The first point where the ray from O along d (the inward normal) meets patch p beyond sMin and
// before *best: Newton on S(u, v) - O - s d = 0 in (u, v, s) from the grid points nearest the ray,
// kept inside the patch, accepted within the patches' accuracy and inside the face's trim.
BRT_SPLIT void ray_patch(const Model* m, int p, real3 Ohi, real3 Olo, real3 d, real sMin, real minCos,
  real* best, int* hitFace, int* hitPatch, real2* hitUV)
{
  const int face = m->patchFace[p];
  __global const real* pd = m->patchDomain + 4 * p;
  __global const real* fd = m->faceDomain + FACE_REALS * face;
  const real3 anchor = anchor_minus(m->patchAnchor + 6 * p, Ohi, Olo);
  // The three grid points nearest the ray (ahead of sMin) start Newton.
  real seedU[3], seedV[3], seedS[3], seedD[3];
  for (int k = 0; k < 3; ++k)
    seedD[k] = REAL_MAX;
  for (int i = 0; i <= 4; ++i)
    for (int j = 0; j <= 4; ++j)
    {
      const real u = pd[0] + (real)0.25 * (real)i * (pd[1] - pd[0]);
      const real v = pd[2] + (real)0.25 * (real)j * (pd[3] - pd[2]);
      const real3 w = anchor + eval_patch_point(m, p, u, v);
      const real sw = dot(w, d);
      const real3 off = w - sw * d;
      real dd = dot(off, off);
      if (!(sw > sMin))
        continue;
      real cu = u, cv = v, cs = sw;
      for (int k = 0; k < 3; ++k)
        if (dd < seedD[k])
        {
          const real tu = seedU[k], tv = seedV[k], ts = seedS[k], td = seedD[k];
          seedU[k] = cu;
          seedV[k] = cv;
          seedS[k] = cs;
          seedD[k] = dd;
          cu = tu;
          cv = tv;
          cs = ts;
          dd = td;
        }
    }
  for (int k = 0; k < 3 && seedD[k] < REAL_MAX; ++k)
  {
    real u = seedU[k], v = seedV[k], s = seedS[k], f2 = REAL_MAX;
    // Accepted within half the patches' accuracy, or the precision's where that is coarser
    // (float with a fine conversion tolerance).
    const real accuracy =
      fmax((real)0.5 * m->slack, (real)32 * REAL_EPS * (fabs(s) + length(anchor)));
    for (int it = 0; it < 20; ++it)
    {
      const PatchEval e = eval_patch(m, p, u, v);
      const real3 F = anchor + e.P - s * d;
      f2 = dot(F, F);
      if (f2 <= (real)4e-6 * accuracy * accuracy)
        break;
      const real J[3][3] = { { e.Du.x, e.Dv.x, -d.x }, { e.Du.y, e.Dv.y, -d.y },
        { e.Du.z, e.Dv.z, -d.z } };
      const real r[3] = { -F.x, -F.y, -F.z };
      real x[3];
      if (!solve3(J, r, x) && !damped3(J, r, x))
        break;
      u = clamp(u + x[0], pd[0], pd[1]);
      v = clamp(v + x[1], pd[2], pd[3]);
      s += x[2];
    }
    // A root: the ray meets the patch there, within a hundredth of half the patches' accuracy
    // or within the precision's rounding where that is coarser (float). A point the ray only
    // passes within the accuracy is a graze, not a hit: counted, a ray skimming a face next to
    // O read 0.00085 where the wall across is 22.57 (the ExpansionCard's sample 10151;
    // `brt_exact_check --ray` on 59 files: grazes 165 -> 21, 148 more rays within 1e-4 relative
    // of OpenCASCADE's first crossing; docs/Solver.md, item 15).
    const real3 F = anchor + eval_patch_point(m, p, u, v) - s * d;
    const real root =
      fmax((real)5e-3 * m->slack, (real)32 * REAL_EPS * (fabs(s) + length(anchor)));
    if (!(dot(F, F) <= root * root) || !(s > sMin) || !(s < *best))
      continue;
    if (minCos > (real)-1)
    {
      // Only where the ray leaves the material through the face at an angle (its outward normal
      // within acos(minCos) of d), not along a face it grazes.
      const PatchEval e = eval_patch(m, p, u, v);
      const real3 n = cross(e.Du, e.Dv) * (m->faceInfo[FACE_INTS * face + 6] ? (real)-1 : (real)1);
      if (!(dot(n, d) >= minCos * length(n)))
        continue;
    }
    // Inside the trim, or on it within the face's UV tolerance (a hit on a seam or an edge
    // belongs to the face, as in ss_on_face).
    int seg;
    real param, trimDist;
    const int inside = classify(m, face, make_real2(u, v), &seg, &param, &trimDist);
    if (!(trimDist <= fd[6]) &&
      (!inside ||
        (trimDist > (real)1e-3 * (fd[1] - fd[0] + fd[3] - fd[2]) && !inside_by_crossings(m, face, u, v))))
      continue;
    *best = s;
    *hitFace = face;
    *hitPatch = p;
    *hitUV = make_real2(u, v);
  }
}

// The slab test: the interval of the ray O + s dir (inv: 1 / dir per coordinate, huge where 0)
// inside box b (min x, y, z, max x, y, z), [*lo, *hi]; empty where *lo > *hi.
inline void ray_box(__global const real* b, real3 O, real3 inv, real* lo, real* hi)
{
  const real tx0 = (b[0] - O.x) * inv.x, tx1 = (b[3] - O.x) * inv.x;
  const real ty0 = (b[1] - O.y) * inv.y, ty1 = (b[4] - O.y) * inv.y;
  const real tz0 = (b[2] - O.z) * inv.z, tz1 = (b[5] - O.z) * inv.z;
  *lo = fmax(fmax(fmin(tx0, tx1), fmin(ty0, ty1)), fmin(tz0, tz1));
  *hi = fmin(fmin(fmax(tx0, tx1), fmax(ty0, ty1)), fmax(tz0, tz1));
}

// The first point of the trimmed faces along the ray from O in direction d beyond sMin and before
// sMax, over the box BVH of the certification (slab test against the ray): faces of solid
// `solid` only (others = 0) or of every solid but it (others = 1), face excludeFace left out
// (-1: none), and with minCos > -1 only where the face's outward normal lies within acos(minCos)
// of d. sMax where nothing is hit (REAL_MAX: no bound).
BRT_SPLIT real ray_first_hit(const Model* m, int solid, int others, int excludeFace, real3 Ohi, real3 Olo,
  real3 d, real sMin, real sMax, real minCos, int* hitFace, int* hitPatch, real2* hitUV)
{
  real best = sMax;
  *hitFace = -1;
  *hitPatch = -1;
  const real3 O = Ohi + Olo; // relative to the model's centre, for the boxes
  const real big = REAL_MAX;
  const real3 inv = make_real3(d.x != (real)0 ? (real)1 / d.x : big,
    d.y != (real)0 ? (real)1 / d.y : big, d.z != (real)0 ? (real)1 / d.z : big);
  const real pad = m->slack; // boxes hold the patches; the ray may graze them
  // Each entry keeps where the ray enters its box (its slab test passed when it was pushed): the
  // nearer child is walked first, and an entry whose box the ray enters beyond the nearest hit
  // found since is dropped when popped. Walked in a fixed order, the rays of the centre test
  // (centre_in_own_solid) searched far patches first, each a Newton, before the hit next to the
  // centre bounded the walk.
  int stack[64];
  real stackLo[64];
  int top = 0;
  {
    real lo, hi;
    ray_box(m->boxNodeBox, O, inv, &lo, &hi);
    if (lo > hi + pad || hi < sMin - pad || lo > best + pad)
      return best;
    stack[top] = 0;
    stackLo[top++] = lo;
  }
  while (top > 0)
  {
    --top;
    const int node = stack[top];
    if (stackLo[top] > best + pad)
      continue;
    __global const int* ni = m->boxNodeInfo + 3 * node;
    if (ni[1] < 0 && (-ni[1] - 1 == solid) == (others != 0))
      continue; // a subtree on one solid (BuildPatchBoxes), not the one asked for
    if (ni[1] > 0)
    {
      for (int i = ni[0]; i < ni[0] + ni[1]; ++i)
      {
        const int item = m->boxItems[i];
        if (!(item < m->patchCount && m->patchFace[item] != excludeFace &&
              (m->faceInfo[FACE_INTS * m->patchFace[item] + 7] == solid) != (others != 0)))
          continue;
        {
          // The patch's own box (BuildPatchBoxes: its trimmed part's control points), widened by
          // what ray_patch accepts a hit within (its accuracy: half the slack, or the precision's
          // over the hit's distance, which lies within the box's farthest corner from O plus
          // that) and the rounding of O and the box: a ray that misses it has no hit there. Each
          // patch a ray's walk reaches costs ray_patch a 5 x 5 grid and up to three Newtons; on
          // the ExpansionCard's ray thickness most of them missed (docs/Solver.md, item 15, "Speed").
          __global const real* pb = m->patchBoxes + 6 * item;
          const real3 a = anchor_minus(m->patchAnchor + 6 * item, Ohi, Olo);
          real D = 0, size = fabs(O.x) + fabs(O.y) + fabs(O.z);
          for (int k = 0; k < 3; ++k)
          {
            const real o = k == 0 ? O.x : (k == 1 ? O.y : O.z);
            D += fmax(fabs(pb[k] - o), fabs(pb[3 + k] - o));
            size += fmax(fabs(pb[k]), fabs(pb[3 + k]));
          }
          const real w = fmax(m->slack,
                           (real)33 * REAL_EPS *
                             ((real)2 * D + length(a) + m->slack)) +
            (real)8 * REAL_EPS * size;
          const real3 b0 = make_real3(pb[0], pb[1], pb[2]) - splat_real3(w);
          const real3 b1 = make_real3(pb[3], pb[4], pb[5]) + splat_real3(w);
          const real tx0 = (b0.x - O.x) * inv.x, tx1 = (b1.x - O.x) * inv.x;
          const real ty0 = (b0.y - O.y) * inv.y, ty1 = (b1.y - O.y) * inv.y;
          const real tz0 = (b0.z - O.z) * inv.z, tz1 = (b1.z - O.z) * inv.z;
          real lo = fmax(fmax(fmin(tx0, tx1), fmin(ty0, ty1)), fmin(tz0, tz1));
          real hi = fmin(fmin(fmax(tx0, tx1), fmax(ty0, ty1)), fmax(tz0, tz1));
          // And the slab between the control points' least and greatest offsets along the
          // patch's mean normal (PATCH_HULL_REALS; relative to its anchor, rounded outwards), as
          // widened: a curved patch's box is loose where the ray passes it obliquely.
          __global const real* h = m->patchHull + PATCH_HULL_REALS * item;
          const real3 n = make_real3(h[3], h[4], h[5]);
          if (h[3] != (real)0 || h[4] != (real)0 || h[5] != (real)0)
          {
            const real na = dot(n, a), nd = dot(n, d);
            const real wn = w + (real)8 * REAL_EPS * (length(a) + fabs(h[6]) + fabs(h[7]));
            const real A = h[6] - wn + na, B = h[7] + wn + na;
            if (nd > (real)0)
            {
              lo = fmax(lo, A / nd);
              hi = fmin(hi, B / nd);
            }
            else if (nd < (real)0)
            {
              lo = fmax(lo, B / nd);
              hi = fmin(hi, A / nd);
            }
            else if (A > (real)0 || B < (real)0)
              continue;
          }
          if (lo > hi || hi < sMin || lo > best)
            continue;
        }
        if (sMax < REAL_MAX)
        {
          // A short ray: a patch whose control hull, or whose face's exact surface, lies farther
          // from O than its end, or wholly behind its start, holds no hit (a hole's wall next
          // to a sample on the plate around it, whose box reaches over the sample).
          real ahead;
          const real reach = sMax + m->slack;
          if (patch_gap(m, item, anchor_minus(m->patchAnchor + 6 * item, Ohi, Olo),
                splat_real3(0), d, &ahead) > reach ||
            ahead < sMin - m->slack ||
            exact_gap(m, m->patchFace[item], Ohi, Olo, splat_real3(0), sMax) > reach)
            continue;
        }
        ray_patch(m, item, Ohi, Olo, d, sMin, minCos, &best, hitFace, hitPatch, hitUV);
      }
      continue;
    }
    if (top + 2 > 64)
      continue;
    const int left = node + 1, right = ni[2];
    real loL, hiL, loR, hiR;
    ray_box(m->boxNodeBox + 6 * left, O, inv, &loL, &hiL);
    ray_box(m->boxNodeBox + 6 * right, O, inv, &loR, &hiR);
    const int okL = !(loL > hiL + pad || hiL < sMin - pad || loL > best + pad);
    const int okR = !(loR > hiR + pad || hiR < sMin - pad || loR > best + pad);
    const int leftFirst = loL <= loR;
    if (leftFirst ? okR : okL)
    {
      stack[top] = leftFirst ? right : left;
      stackLo[top++] = leftFirst ? loR : loL;
    }
    if (leftFirst ? okL : okR)
    {
      stack[top] = leftFirst ? left : right;
      stackLo[top++] = leftFirst ? loL : loR;
    }
  }
  return best;
}

// The ray thickness at O: the distance along d to the first point of the trimmed faces of O's
// solid beyond twice the patches' accuracy (O itself lies on its face), moved onto the exact
// surface where the face hit is analytic. REAL_MAX where nothing is hit (an open solid, or the
// boxes are not there).
real ray_thickness(const Model* m, int ownFace, real3 Ohi, real3 Olo, real3 d, real stepTol,
  int* hitFace)
{
  *hitFace = -1;
  if (!(m->mode & MODE_CERTIFY))
    return REAL_MAX;
  int patch;
  real2 uv;
  real best = ray_first_hit(m, m->faceInfo[FACE_INTS * ownFace + 7], 0, -1, Ohi, Olo, d,
    (real)2 * m->slack, REAL_MAX, (real)-2, hitFace, &patch, &uv);
  if (*hitFace >= 0 && best < REAL_MAX)
    best = exact_ray_hit(m, *hitFace, Ohi, Olo, d, best, stepTol);
  return best;
}

// A wall across O thinner than the patches resolve: the first point of another face of O's solid
// along d within 2 slack (4 tolerances) of O, beyond rounding (and a thousandth of the slack),
// where the ray leaves the material through it (its outward normal within 60 degrees of d: not a
// face through O that the ray grazes, as at a sample on an edge);
// REAL_MAX where there is none, the certification is off, or the precision cannot tell (float on
// a large model). Within 4 tolerances of O the certification counts nothing (consider_point), and
// a contact there is the trivial one (near_sample), so a sphere across such a wall is not the
// wall's: it fails, or passes through the wall to whatever lies beyond (a 0.2 um plate read 2.7
// to 4.9 mm, which CheckResults flags Unbounded).
BRT_SPLIT real thin_wall_across_at(const Model* m, int ownFace, real3 Ohi, real3 Olo, real3 d,
  real scale, int* face, int* patch, real2* uv)
{
  *face = -1;
  if (!(m->mode & MODE_CERTIFY) || (m->mode & MODE_EXTERIOR))
    return REAL_MAX;
  const real sMin = (real)256 * REAL_EPS * scale;
  const real sMax = (real)2 * m->slack;
  if (!(sMin < sMax))
    return REAL_MAX;
  const real s = ray_first_hit(m, m->faceInfo[FACE_INTS * ownFace + 7], 0, ownFace, Ohi, Olo, d,
    sMin, sMax, (real)0.5, face, patch, uv);
  return *face >= 0 && s < sMax ? s : REAL_MAX;
}

real thin_wall_across(const Model* m, int ownFace, real3 Ohi, real3 Olo, real3 d, real scale)
{
  int face, patch;
  real2 uv;
  return thin_wall_across_at(m, ownFace, Ohi, Olo, d, scale, &face, &patch, &uv);
}

// A wall across O thinner than 2 slack (thin_wall_across) between faces that meet at an angle of
// more than 10 degrees is a wedge: O lies within a few slack of the edge where its face meets the
// face the ray leaves through (the two tangent planes meet at w / tan(angle) from O), and the
// maximal sphere at O is the two planes' in-sphere, of diameter 2t = w 2 cos(a) / (1 + cos(a)) for
// the wall w and the angle a between d and that face's outward normal n, touching the face at
// t (d + n) from O. A thread's flank where it runs out through a plate's top face at 30 degrees
// (Voron's MIC6 bed plates: 12 samples of 20,484 whose mesh vertices lie 3e-5 off the edge)
// is the case: a sharp edge, resolved at any tolerance, where the sphere is about 0 as at any
// such edge. A plate or a knife edge (the faces within 10 degrees of parallel: a knife edge's
// walls thinner than 2 slack lie within 3 degrees of its tangent point for radii from 1 mm) stays
// ThinWall, which a finer tolerance resolves or nothing does. Returns 0 where the wall is not
// thin, 1 for a plate or knife edge, 2 for a wedge, with *r its sphere.
inline int thin_wall_or_wedge(const Model* m, int ownFace, real3 Ohi, real3 Olo, real3 d,
  real scale, Result* r)
{
  int face, patch;
  real2 uv;
  const real w = thin_wall_across_at(m, ownFace, Ohi, Olo, d, scale, &face, &patch, &uv);
  if (!(w < REAL_MAX))
    return 0;
  const PatchEval e = eval_patch(m, patch, uv.x, uv.y);
  real3 n = cross(e.Du, e.Dv) * (m->faceInfo[FACE_INTS * face + 6] ? (real)-1 : (real)1);
  const real ln = length(n);
  if (!(ln > (real)0))
    return 1;
  n = n / ln;
  const real c = dot(n, d);
  if (!(c < (real)0.98480775)) // cos 10 degrees
    return 1;
  const real t = w * c / ((real)1 + c);
  Result w2 = no_result();
  w2.type = CONTACT_SURFACE_SURFACE;
  w2.reason = FAIL_NONE;
  w2.t = t;
  w2.foot = t * (d + n);
  w2.param = uv;
  w2.face = face;
  w2.patch = patch;
  *r = w2;
  return 2;
}

// The verdict on a sample across a wall thinner than 2 slack: a plate or knife edge fails it as
// FAIL_THIN_WALL, a wedge gives it the wedge's sphere (thin_wall_or_wedge); otherwise r stays.
inline void thin_wall_verdict(const Model* m, int ownFace, real3 Ohi, real3 Olo, real3 d,
  real scale, Result* r)
{
  Result wedge;
  const int k = thin_wall_or_wedge(m, ownFace, Ohi, Olo, d, scale, &wedge);
  if (k == 1)
  {
    r->type = CONTACT_FAILED;
    r->reason = FAIL_THIN_WALL;
  }
  else if (k == 2)
    *r = wedge;
}

// A failed sample across a wall thinner than 2 slack (thin_wall_across) fails as FAIL_THIN_WALL,
// which says why and what to do (a finer conversion tolerance), unless the wall is a wedge
// (thin_wall_or_wedge), which gives the sphere. Only failed samples are asked: the ray on every
// sample cost 8% (NIST_MBE_PMI_11) to 20% (the ExpansionCard) of the solve, and a sphere that
// passes through such a wall to whatever lies beyond stays as solved unless its solid's box
// bounds it (CheckResults' Unbounded, which brt::NameThinWalls then names; docs/Robustness.md,
// item 8 and Open).
inline void flag_thin_wall(const Model* m, int ownFace, real3 Ohi, real3 Olo, real3 d, real scale,
  Result* r)
{
  if (r->type == CONTACT_FAILED)
    thin_wall_verdict(m, ownFace, Ohi, Olo, d, scale, r);
}

// (M - P).n_out / |n| at (u, v) of `face`: how far the sphere's centre lies on the outer side of
// the face's tangent plane at the foot (n_out its outward normal, as surface_newton's side);
// 0 where the face has no normal there. q = M - P.
inline real centre_side(const Model* m, int face, real u, real v, real3 q)
{
  const int patch = find_patch(m, face, u, v);
  const PatchEval e = eval_patch(m, patch, u, v);
  const real3 n = cross(e.Du, e.Dv);
  const real ln = length(n);
  if (!(ln > (real)0))
    return 0;
  return dot(q, n) / ln * (m->faceInfo[FACE_INTS * face + 6] ? (real)-1 : (real)1);
}

// One ray's vote on whether its start lies inside a solid (solid and others as ray_first_hit):
// 1 where the first face it meets beyond sMin has its outward normal along the ray (the ray
// leaves the material there), -1 where against it, 0 where it meets nothing; *face the face met.
BRT_SPLIT int ray_vote(const Model* m, int solid, int others, real3 Ohi, real3 Olo, real3 dir, real sMin,
  int* face)
{
  int p;
  real2 uv;
  const real s =
    ray_first_hit(m, solid, others, -1, Ohi, Olo, dir, sMin, REAL_MAX, (real)-2, face, &p, &uv);
  if (*face < 0 || !(s < REAL_MAX))
    return 0;
  const PatchEval e = eval_patch(m, p, uv.x, uv.y);
  const real3 n = cross(e.Du, e.Dv) * (m->faceInfo[FACE_INTS * *face + 6] ? (real)-1 : (real)1);
  return dot(n, dir) > (real)0 ? 1 : -1;
}

// The three rays' directions: a along `a`, then tilted 0.5 rad from it two ways (tan = 0.55).
inline real3 vote_direction(real3 a, int k)
{
  const real3 x = fabs(a.x) < (real)0.9 ? make_real3(1, 0, 0) : make_real3(0, 1, 0);
  const real3 u = normalize(cross(a, x));
  const real3 v = cross(a, u);
  return k == 0 ? a : normalize(a + (real)0.55 * (k == 1 ? u : v));
}

// Whether the sphere's centre M = O + t d lies inside O's solid: three rays from M (towards O,
// and tilted 0.5 rad from that two ways), each voting inside where the first face of the solid
// it meets has its outward normal along the ray (it leaves the material there), outside where
// that normal points against it or it meets nothing; two votes decide, so one face the file
// orients the wrong way does not.
BRT_SPLIT int centre_in_own_solid(const Model* m, int ownFace, real3 Ohi, real3 Olo, real3 d, real t,
  real scale)
{
  const int solid = m->faceInfo[FACE_INTS * ownFace + 7];
  const real3 Mlo = Olo + t * d; // the rays start at M (anchor_minus subtracts Ohi + Mlo)
  const real sMin = (real)256 * REAL_EPS * scale;
  int inside = 0, outside = 0;
  for (int k = 0; k < 3 && inside < 2 && outside < 2; ++k)
  {
    int f;
    // (A miss votes outside: from inside a closed solid every ray leaves it somewhere.)
    if (ray_vote(m, solid, 0, Ohi, Mlo, vote_direction(-d, k), sMin, &f) > 0)
      ++inside;
    else
      ++outside;
  }
  return inside >= 2;
}

// A sphere in the air. The sphere is tangent at O from the material's side, and a sphere that
// holds no boundary lies in the material whole, but within 4 tolerances of O the certification
// counts nothing: across a wall thinner than that (two faces meeting tangentially with the
// material between them, a knife edge; an acute edge; a plate thinner than the conversion
// resolves) the sphere passes into the air beyond and grows there until it touches the boundary
// from outside. Such a contact is seen from the outer side of its face's tangent plane (a surface
// contact), or of one of its edge's two faces' planes (an edge contact: a sphere in the material
// touches a concave edge from the inner side of both, and no convex edge), by more than the
// clearance and half the slack (from_inside's allowance).
// Those candidates, and only they (a few in ten thousand samples), have the centre tested against
// the solid (centre_in_own_solid: one face the file orients the wrong way shows a candidate
// whose centre lies inside), and a centre outside with the wall across O thinner than 2 slack
// (thin_wall_across, the ray along d) fails the sample as ThinWall, or gives it the wedge's sphere
// (thin_wall_or_wedge). A centre outside with a
// thicker wall across is left as it was: O on a piece of face that a sloppy file lets stand out
// into the air past the fillet next to it (the unseen cover: 24 spheres of 2t = 0.004 to 0.01 at
// such edges), where the sphere there is about 0 as at any convex edge. Vertex contacts are left
// as they are: other faces meet there.
BRT_SPLIT void reject_contact_from_outside(const Model* m, int ownFace, real3 Ohi, real3 Olo,
  real3 d, real scale, Result* r)
{
  // (A sphere of radius up to 4 slack, next to a convex edge where the sphere is about 0 by
  // definition, straddles the patches' accuracy: its centre's side says nothing. A 0.5 mm tube's
  // rim samples read 2t = 1e-3 with their centre 3e-4 off the inner wall's patches.)
  if (!(m->mode & MODE_CERTIFY) || (m->mode & MODE_EXTERIOR) || r->face < 0 ||
    (r->type != CONTACT_SURFACE_SURFACE && r->type != CONTACT_SURFACE_EDGE) ||
    !(r->t > (real)4 * m->slack))
    return;
  const real3 q = r->t * d - r->foot; // M - P
  const real allowed = m->delta + (real)0.5 * m->slack;
  int outside = 0;
  if (r->type == CONTACT_SURFACE_SURFACE)
  {
    if (r->face == ownFace)
      return; // (self contacts: their own rules)
    outside = centre_side(m, r->face, r->param.x, r->param.y, q) > allowed;
  }
  else
  {
    if (r->edge < 0)
      return;
    for (int k = 0; k < 2 && !outside; ++k)
    {
      const int f = m->edgeInfo[4 * r->edge + 2 + k];
      real u, v;
      if (f >= 0 && m->faceInfo[FACE_INTS * f + 1] > 0 &&
        edge_point_on_face(m, f, r->edge, r->param.x, &u, &v))
        outside = centre_side(m, f, u, v, q) > allowed;
    }
  }
  if (outside && !centre_in_own_solid(m, ownFace, Ohi, Olo, d, r->t, scale))
    thin_wall_verdict(m, ownFace, Ohi, Olo, d, scale, r);
}

// The gap with all solids: whether O, on a face of its solid, lies on or inside another solid
// (two solids of an assembly that touch there, or overlap). Rays from O (along the outward
// normal d, then tilted 0.5 rad from it two ways) to the first face of another solid beyond four
// times the patches' accuracy and the precision's (a face of the other solid through O itself is
// not hit): where that face's outward normal points along the ray, the ray leaves that solid, so
// O lies in it. A first ray that meets nothing decides (outside); else two of three. *face: the
// other solid's face hit (-1 when outside).
BRT_SPLIT int inside_other_solid(const Model* m, int ownFace, real3 Ohi, real3 Olo, real3 d, real scale,
  int* face)
{
  *face = -1;
  if (!(m->mode & MODE_CERTIFY))
    return 0;
  const int solid = m->faceInfo[FACE_INTS * ownFace + 7];
  // Beyond the patches' accuracy and the precision's (float: a face through O must not count).
  const real sMin = fmax((real)4 * m->slack, (real)256 * REAL_EPS * scale);
  int inside = 0, outside = 0;
  for (int k = 0; k < 3 && inside < 2 && outside < 2; ++k)
  {
    int f;
    const int vote = ray_vote(m, solid, 1, Ohi, Olo, vote_direction(d, k), sMin, &f);
    if (vote == 0 && k == 0)
      return 0;
    if (vote > 0)
    {
      ++inside;
      *face = f;
    }
    else
      ++outside;
  }
  if (inside < 2)
    *face = -1;
  return inside >= 2;
}

// The shrinking ball: from the sphere of r (radius r->t, tangent at O), while a point of the
// trimmed faces lies deeper than `depth` inside it, the sphere through the deepest one (eq. 1 with
// the depth as clearance: that point then lies exactly `depth` inside) replaces it. Each step
// shrinks the sphere; it stops when no point is deeper, and r becomes a contact at the last
// point (residual: the last step). The fallback where no Newton or descent from a point inside
// shrinks the sphere (a sample next to a convex edge, a drafted wall). 0 where nothing was found
// inside, the certification is off, or it does not settle in 32 steps. first, when given, is
// find_point_inside's answer for r's sphere at this depth, which the caller already has: the
// first step starts from it instead of asking again (the same query gives the same answer).
BRT_SPLIT int shrink_ball(const Model* m, int ownFace, real3 Ohi, real3 Olo, real3 d, real depth,
  int nearOwn, const PointInside* first, Result* r)
{
  if (!(m->mode & MODE_CERTIFY))
    return 0;
  real t = r->t, step = 0;
  PointInside st, last;
  last.found = 0;
  last.face = last.edge = -1;
  last.onTrim = 0;
  last.u = last.v = last.t = last.T = 0;
  last.w = splat_real3(0); // (read only once found; set here for the compilers' sake)
  for (int k = 0; k < 32; ++k)
  {
    int found;
    if (k == 0 && first)
    {
      st = *first;
      found = st.found;
    }
    else
      found = find_point_inside(m, ownFace, Ohi, Olo, d, t, depth, &st);
    if (!found)
    {
      if (!last.found)
        return 0;
      // The foot is the deepest point itself: on an edge, the face's (u, v) from its trim
      // is only a start, and a file's trim may not meet its edge.
      Result c = no_result();
      c.face = last.face;
      c.t = t;
      c.res = step;
      c.foot = last.w;
      if (last.edge >= 0)
      {
        c.type = at_edge_end(m, last.edge, last.T) ? CONTACT_SURFACE_VERTEX : CONTACT_SURFACE_EDGE;
        c.edge = last.edge;
        c.param = make_real2(last.T, 0);
      }
      else
      {
        c.type = CONTACT_SURFACE_SURFACE;
        c.patch = find_patch(m, last.face, last.u, last.v);
        c.param = make_real2(last.u, last.v);
        // Touched from outside: the ball's centre beyond the face's tangent plane at the last
        // point by more than half the radius, for a sphere above 100 slack (the last point is a
        // search's, not an exact extremum: from_inside's allowance, the clearance, and then half
        // the radius alone failed 0.15-0.18% of the tile's and the hinge's samples, spheres of a
        // few slack at their corners). Where a file's face folds under its neighbour
        // (RWTH-E3D's enclosure_top.stp: a roof's B-spline below the floor next to their knife
        // edge), the ball shrank onto the floor from below, its centre in the air.
        // (A point on the face's trim is the edge's: its face's normal does not tell the side.)
        if (c.patch >= 0 && !last.onTrim && c.face != ownFace)
        {
          const PatchEval e = eval_patch(m, c.patch, last.u, last.v);
          const real3 n = cross(e.Du, e.Dv) *
            (m->faceInfo[FACE_INTS * c.face + 6] ? (real)-1 : (real)1);
          const real ln = length(n);
          if (ln > (real)0 && t > (real)100 * m->slack && dot(t * d - c.foot, n) / ln > (real)0.5 * t)
          {
            r->touchedOutside = 1;
            return 0;
          }
        }
      }
      // A contact on O's own face next to O is the trivial or an osculating solution, not a
      // wall (as for Newton's contacts). On an edge only O itself is (as for eq. 7's contacts):
      // an edge of O's own face that rises into the sphere, however shallow, is its curve
      // standing off the face (the file's tolerance), geometry the sphere must not hold; so is
      // a point where O's own face ends (on its trim), whose place the trim fixes, not the
      // face's curvature; and so is a shallow point of an own face whose patches are its surface
      // (own_face_margin), where their accuracy fixes the radius; with nearOwn, also one of a
      // free-form own face within half the radius of O, counted there beyond its patches'
      // measured deviation (own_face_margin_near), within which the ball then holds it.
      // With nearOwn 2 (settle_not_maximal's last resort), a point of O's own face a tenth of
      // the radius or more in front of O counts as well: a round whose own curvature bounds the
      // sphere, which touches it along its arc (the radius then fixed to the depth over 1 - cos
      // of the angle at the centre, at most ten depths; the caller's polish refines it).
      const int round = nearOwn == 2 && c.face == ownFace && !last.onTrim;
      if (c.edge >= 0 ? edge_at_sample(m, ownFace, c.edge, c.foot)
          : round ? at_sample(m, ownFace, c.face, c.foot) || !(dot(c.foot, d) >= (real)0.1 * t)
          : (last.onTrim || own_face_margin(m, c.face) == (real)0 ||
                (nearOwn && c.face == ownFace && dot(c.foot, c.foot) < (real)0.25 * t * t &&
                  own_face_margin_near(m, c.face) < own_face_margin(m, c.face))
                ? at_sample(m, ownFace, c.face, c.foot)
                : shallow_own_face_contact(m, ownFace, c.face, c.foot, d,
                    sphere_radius(d, c.foot, (real)0))))
        return 0;
      *r = c;
      return 1;
    }
    if (!(st.t < t) || !(st.t > (real)0))
      return 0;
    step = t - st.t;
    t = st.t;
    last = st;
  }
  return 0;
}

// A contact on O's own face or on one of its edges.
inline int on_own_face(const Model* m, int ownFace, const Result* r)
{
  return r->edge >= 0
    ? m->edgeInfo[4 * r->edge + 2] == ownFace || m->edgeInfo[4 * r->edge + 3] == ownFace
    : r->face == ownFace;
}

// The last resort of a sphere no restart shrinks: the shrinking ball through the deepest point
// of the faces (where it ends on a shallow point of O's own face, item 10's osculating case, the
// descent on that face from the first point inside instead, as the descent fallback would; on a
// free-form face near O, where that descent runs back to O or the first point lies elsewhere,
// the ball's own sphere),
// then through the edges' s1 points still inside it. Such a point lies on an edge
// near O where the certification counts nothing (an edge whose curve the file lets stray from
// its face by more than the conversion tolerance, up to 1.5e-3 mm on the ExpansionCard), and no
// Newton from a face reaches it: the sphere is then bounded by the edge's curve itself, at the
// minimum of eq. 1 along the edge from that point (eq. 7's contact where it converges).
// Each sphere lies inside the one before (tangent at O, smaller), so what the certification
// cleared stays clear. 1 with r the settled sphere; 0 where it does not settle (NotMaximal).
// known, when given, is find_point_inside's answer for r's sphere at check_depth, which the
// caller already has (the certification's query in solve_with_clearance): neither this nor the
// shrinking ball asks it again. On Voron-0's SKR E3 DIN mount 2,212 of 46,030 samples (4.8%)
// come here and took 39% of the solve, a third of it in those two repeated queries, each of the
// sphere found too large, which reaches the most patches (docs/Solver.md, item 14).
BRT_SPLIT int settle_not_maximal(const Model* m, __global const real* s1Point,
  __global const int* s1Face, __global const real* s1UV, __global const real* nodeBox,
  __global const int* nodeInfo, int ownFace, real3 Ohi, real3 Olo, real3 d, real scale,
  real newtonTol, int maxIterations, int maxEdgeIterations, int* iterations,
  const PointInside* known, Result* r)
{
  const real depth = check_depth(m, scale);
  const int solid = scope_solid(m, ownFace);
  PointInside inside;
  if (known)
    inside = *known;
  if ((known ? known->found : find_point_inside(m, ownFace, Ohi, Olo, d, r->t, depth, &inside)) &&
    !shrink_ball(m, ownFace, Ohi, Olo, d, depth, 0, &inside, r))
  {
    // A free-form own face whose points count near O by its measured deviation.
    const int freeForm = own_face_margin_near(m, ownFace) < own_face_margin(m, ownFace);
    if (inside.edge >= 0 || inside.face != ownFace)
      return freeForm && shrink_ball(m, ownFace, Ohi, Olo, d, depth, 1, &inside, r);
    const Result dr = descend(m, ownFace, ownFace, Ohi, Olo, d, inside.u, inside.v, scale,
      newtonTol, maxIterations, maxEdgeIterations, iterations);
    PointInside again;
    // The descent's sphere where it shrinks this one and holds no point. On a free-form face
    // whose points count near O by its measured deviation (own_face_margin_near), where its
    // contact on O's own face or its edges stands no more than the slack in front of O's tangent
    // plane, the shrinking ball's own sphere ended on that face's point (shrink_ball), whose
    // radius the measured deviation then fixes, comes first: from a point of such a face curving
    // into the sphere away from O, the descent can run back to O, to the wrinkle of an edge's
    // curve a few micrometres off that plane next to it (a Ventilator blade 2 mm thick read
    // 0.49925).
    const int valid = dr.type != CONTACT_FAILED && dr.t < r->t &&
      !find_point_inside(m, ownFace, Ohi, Olo, d, dr.t, depth, &again);
    const int nearOwn = freeForm &&
      (!valid || (on_own_face(m, ownFace, &dr) && !(dot(d, dr.foot) > m->slack)));
    if (!(nearOwn && shrink_ball(m, ownFace, Ohi, Olo, d, depth, 1, &inside, r)))
    {
      // Last, a round of O's own face whose curvature bounds the sphere: the ball's point on it
      // well in front of O (shrink_ball, nearOwn 2).
      if (!valid && !shrink_ball(m, ownFace, Ohi, Olo, d, depth, 2, &inside, r))
        return 0;
      if (valid)
        *r = dr;
    }
  }
  for (int k = 0; k < 4; ++k)
  {
    real t;
    const int best = verify_s1(m, s1Point, s1Face, nodeBox, nodeInfo, Ohi + Olo, d, solid, scale,
      r->t, depth, &t);
    if (best < 0)
      return 1;
    if (s1Face[best] >= 0)
      return 0; // a face's point: the certification's to find, not this rescue's
    const int face = ~s1Face[best];
    int seg;
    real param, dist;
    classify(m, face, make_real2(s1UV[2 * best], s1UV[2 * best + 1]), &seg, &param, &dist);
    if (seg < 0 || m->trimEdge[seg] < 0)
      return 0;
    const int edge = m->trimEdge[seg];
    const real T = m->trimRange[2 * seg] + param * (m->trimRange[2 * seg + 1] - m->trimRange[2 * seg]);
    const EdgeMinimum em = minimise_on_edge(m, edge, T, Ohi, Olo, d, scale, maxEdgeIterations,
      iterations);
    if (!(em.t < r->t) || !(em.t > (real)0))
      return 0;
    Result c = edge_contact(m, ownFace, face, edge, &em, d, newtonTol);
    if (c.type == CONTACT_FAILED)
    {
      // Not converged or next to O: the minimum is still a point of the edge on the sphere.
      c = no_result();
      c.type = em.atEnd || at_edge_end(m, edge, em.T) ? CONTACT_SURFACE_VERTEX
                                                      : CONTACT_SURFACE_EDGE;
      c.face = face;
      c.edge = edge;
      c.t = em.t;
      c.foot = em.C;
      c.param = make_real2(em.T, 0);
    }
    *r = c;
  }
  return 0;
}

// The patch of `face` whose control-point box lies nearest to P (relative to the model's
// centre), within `reach`: a scan of the face's patches. -1 where none lies that near.
int nearest_patch_of_face(const Model* m, int face, real3 P, real reach)
{
  __global const int* fi = m->faceInfo + FACE_INTS * face;
  int best = -1;
  real best2 = reach * reach;
  for (int p = fi[0]; p < fi[0] + fi[1] * fi[2]; ++p)
  {
    const real g2 = box_gap2(m->patchBoxes + 6 * p, P);
    if (g2 < best2)
    {
      best2 = g2;
      best = p;
    }
  }
  return best;
}

// The point of `face` nearest to O from (u, v) on it: Gauss-Newton on |S(u, v) - O|^2 over its
// patches (face_gauss_newton_step, as project_on_face_near, here for a point off the face; at
// most 8 steps). 1 with (u, v) and the point (relative to O) where the last step lands inside
// the face's trim.
BRT_SPLIT int nearest_on_face(const Model* m, int face, real3 Ohi, real3 Olo, real* uio, real* vio,
  real3* point)
{
  real u = *uio, v = *vio;
  __global const real* fd = m->faceDomain + FACE_REALS * face;
  int patch = find_patch(m, face, u, v);
  for (int it = 0; it < 8; ++it)
  {
    const real step = face_gauss_newton_step(m, face, Ohi, Olo, splat_real3(0), (real)-1, &u,
      &v, &patch);
    if (step < (real)0)
      return 0;
    if (step <= (real)1e-9 * (fd[1] - fd[0] + fd[3] - fd[2]))
      break;
  }
  // Unsettled after the steps (Gauss-Newton goes linearly at a distance from a curved face) is
  // good enough: the point is a start, and its own radius is what counts.
  int seg;
  real param, trimDist;
  if (!classify(m, face, make_real2(u, v), &seg, &param, &trimDist))
    return 0;
  *uio = u;
  *vio = v;
  *point = eval_patch_point(m, patch, u, v) + anchor_minus(m->patchAnchor + 6 * patch, Ohi, Olo);
  return 1;
}

// A start across a thin wall (brt::BuildWallPartners): where s1 is much coarser than the wall,
// eq. 1 over it finds its best point far to the side, often on the narrow face that closes the
// wall, and the solve from there goes through failed Newtons and restarts. Of the faces across
// O's thin walls (FACE_INTS slots 12 on) with an exact surface, the one whose surface's point
// nearest to O gives the smallest radius t_delta, where that is below half of *t: its point
// nearest to O on its patches (Gauss-Newton from the middle of its patch nearest to that point)
// is one more point of eq. 1, and replaces the start where its t_delta is smaller than *t. 1
// where it did.
BRT_SPLIT int wall_partner_start(const Model* m, int ownFace, real3 Ohi, real3 Olo, real3 d, real* t,
  int* startFace, real* startU, real* startV)
{
  // Each partner's exact surface: its point nearest to O and the radius through it.
  real tw[WALL_PARTNERS];
  real3 across[WALL_PARTNERS];
  int faces[WALL_PARTNERS];
  int n = 0;
  for (int k = 0; k < WALL_PARTNERS; ++k)
  {
    const int f = m->faceInfo[FACE_INTS * ownFace + 12 + k];
    if (f < 0)
      break;
    const int kind = m->faceInfo[FACE_INTS * f + 8];
    if (kind == EXACT_NONE)
      continue;
    __global const real* e = m->faceDomain + FACE_REALS * f + FACE_EXACT;
    real3 g;
    int ok;
    const real dist = exact_distance(kind, e, -anchor_minus(e, Ohi, Olo), &g, &ok);
    if (!ok)
      continue;
    across[n] = -dist * g; // relative to O
    tw[n] = sphere_radius(d, across[n], m->delta);
    faces[n++] = f;
  }
  // The smallest radius first, below half of *t, on a face whose patches reach that point (the
  // exact surface goes on past the face).
  for (int tries = 0; tries < n; ++tries)
  {
    int k = -1;
    for (int j = 0; j < n; ++j)
      if (faces[j] >= 0 && tw[j] < (real)0.5 * *t && (k < 0 || tw[j] < tw[k]))
        k = j;
    if (k < 0)
      return 0;
    const int face = faces[k];
    faces[k] = -1;
    const int patch = nearest_patch_of_face(m, face, Ohi + Olo + across[k], m->slack);
    if (patch < 0)
      continue;
    __global const real* pd = m->patchDomain + 4 * patch;
    real u = (real)0.5 * (pd[0] + pd[1]), v = (real)0.5 * (pd[2] + pd[3]);
    real3 w;
    if (!nearest_on_face(m, face, Ohi, Olo, &u, &v, &w))
      continue;
    const real r = sphere_radius(d, w, m->delta);
    if (!(r < *t))
      continue;
    *t = r;
    *startFace = face;
    *startU = u;
    *startV = v;
    return 1;
  }
  return 0;
}

// Refines a contact found in lower precision: the same contact's Newton from
// its foot (eq. 4 on its face from the foot's (u, v), or the minimum along its edge from T), then
// the local part of the second look, and keeps the result where the Newton converged within rho
// of the old foot. r carries the foot relative to O and the foot's parameters; m->delta is the
// clearance of the pass that found it. 1 where r was replaced.
BRT_SPLIT int polish_result(const Model* m, int ownFace, real3 Ohi, real3 Olo, real3 d, real scale,
  real stepTol, real newtonTol, int maxIterations, int maxEdgeIterations, int* iterations,
  Result* r)
{
  if (r->type == CONTACT_FAILED || r->type == CONTACT_OTHER_SOLID ||
    r->type == CONTACT_OSCULATING)
    return 0;
  const real reported = sphere_radius(d, r->foot, (real)0);
  const real tDelta = sphere_radius(d, r->foot, m->delta);
  Result c = no_result();
  if (r->type == CONTACT_SURFACE_SURFACE &&
    shallow_own_face_contact(m, ownFace, r->face, r->foot, d, reported))
  {
    // Only the descent finds such a contact (an osculating sphere next to O, on a concave
    // round): Newton from it goes to the trivial solution P = O. Descend again.
    c = descend(m, ownFace, r->face, Ohi, Olo, d, r->param.x, r->param.y, scale, newtonTol,
      maxIterations, maxEdgeIterations, iterations);
  }
  else if (r->type == CONTACT_SURFACE_SURFACE)
  {
    const SurfaceSolve ss = surface_newton(m, r->face, Ohi, Olo, d, r->param.x, r->param.y,
      tDelta > (real)0 && tDelta < REAL_MAX ? tDelta : reported, scale, stepTol, newtonTol,
      maxIterations, iterations);
    if (valid_surface_solve(m, ownFace, r->face, &ss, d, scale, newtonTol))
      c = surface_result(r->face, &ss);
  }
  else if (r->edge >= 0)
  {
    // A vertex: the edge's end exactly (a float T is the end rounded).
    real T = r->param.x;
    if (r->type == CONTACT_SURFACE_VERTEX)
    {
      const real T0 = m->edgeRange[4 * r->edge], T1 = m->edgeRange[4 * r->edge + 1];
      T = fabs(T - T1) < fabs(T - T0) ? T1 : T0;
    }
    const EdgeMinimum em =
      minimise_on_edge(m, r->edge, T, Ohi, Olo, d, scale, maxEdgeIterations, iterations);
    c = edge_contact(m, ownFace, r->face, r->edge, &em, d, newtonTol);
  }
  if (c.type == CONTACT_FAILED)
    return 0;
  const real rho = fmax((real)1e-2 * reported, (real)10 * m->slack);
  const real3 moved = c.foot - r->foot;
  if (dot(moved, moved) > rho * rho)
    return 0;
  second_look_near(m, ownFace, Ohi, Olo, d, scale, stepTol, newtonTol, maxIterations,
    maxEdgeIterations, iterations, &c);
  *r = c;
  return 1;
}

// The start a chain's previous sample hands on (solve_chain): the face of its contact across and
// the contact's (u, v) there; face -1: none.
typedef struct
{
  int face;
  real u, v;
} Hint;

// eq. 1's sphere through the hint's point P (w = P - O): where P stands in front of O as
// initialise asks of an s1 point, 1 with its radius in *t. An upper bound of the maximal sphere,
// as eq. 1 through any point of the faces is.
inline int hint_start(const Model* m, const Hint* h, int solid, int notStart, real3 Ohi,
  real3 Olo, real3 d, real scale, real* t, real3* w)
{
  if (h->face < 0 || h->face == notStart || !in_scope(m->faceInfo, h->face, solid))
    return 0;
  const int p = find_patch(m, h->face, h->u, h->v);
  *w = eval_patch_point(m, p, h->u, h->v) + anchor_minus(m->patchAnchor + 6 * p, Ohi, Olo);
  real minDist, noise;
  start_tolerances(scale, &minDist, &noise);
  const real e = dot(d, *w) - m->delta, l2 = dot(*w, *w);
  if (!starts_eq1(e, l2, noise, minDist))
    return 0;
  *t = (real)0.5 * (l2 - m->delta * m->delta) / e;
  return *t < scale;
}

// One sample at the clearance m->delta: initialisation (eq. 1),
// steps 4-7, the descent fallback, then the verification that the sphere is maximal: an s1 point
// more than delta inside it restarts the solve there, at most 3 times.
BRT_SPLIT Result solve_with_clearance(const Model* m, __global const real* s1Point,
  __global const int* s1Face, __global const real* s1UV, __global const real* nodeBox,
  __global const int* nodeInfo, int ownFace, real2 ownUV, real3 Ohi, real3 Olo, real3 d,
  real scale, real stepTol, real newtonTol, int maxIterations, int maxEdgeIterations,
  const Hint* hint, int* iterations)
{
  __global const int* faceInfo = m->faceInfo;
  const real3 O = Ohi + Olo; // for the initialisation, where rounding does not matter
  const int solid = scope_solid(m, ownFace);
  // O on a cylinder, cone, sphere or torus, on its convex side: its own face's points give no start.
  // Such a face touches a sphere tangent at O nowhere else below the sphere across its axis,
  // centre or core circle, which the closed form gives after the solve (self_contact_radius);
  // eq. 4 from them wanders and stops unconverged (a third of the ExpansionCard's samples did,
  // before the best start on another face was tried). The verification and the certification
  // still count the face's points.
  int notStart = -1, selfContact = 0;
  real tSelf = 0;
  if (!(m->mode & MODE_EXTERIOR))
  {
    __global const real* e = m->faceDomain + FACE_REALS * ownFace + FACE_EXACT;
    selfContact = self_contact_radius(faceInfo[FACE_INTS * ownFace + 8], e,
      -anchor_minus(e, Ohi, Olo), d, m->slack, &tSelf);
    if (selfContact)
      notStart = ownFace;
  }
  // O on a plane: its own face's points lie in O's tangent plane (to the patches' deviation from
  // the plane, here below 1e-9 of the model's size), where no start counts (initialise); left
  // out, the walk skips the face's subtrees around O whole.
  if (faceInfo[FACE_INTS * ownFace + 8] == EXACT_PLANE)
  {
    const real dev = m->faceDomain[FACE_REALS * ownFace + FACE_DEVIATION];
    if (dev >= (real)0 && dev <= (real)1e-9 * scale)
      notStart = ownFace;
  }
  // The start: eq. 1 through the previous sample's contact where a chain hands one on (the
  // sample next to it in SpatialOrder mostly touches the same face near there), else eq. 1's
  // minimum over s1. Either is an upper bound of the maximal sphere and only starts the solve:
  // the certification below decides whether the sphere is empty (docs/Solver.md, "Chains").
  real t;
  real3 hintW = splat_real3(0);
  const int hinted = hint_start(m, hint, solid, notStart, Ohi, Olo, d, scale, &t, &hintW);
  int best = hinted ? -1 : initialise(s1Point, s1Face, faceInfo, nodeBox, nodeInfo, O, d, solid,
    notStart, scale, REAL_MAX, m->delta, 0, &t);
  Result r = no_result();
  // The gap: where no s1 point lies in front of O, or even the first sphere (eq. 1 over s1, an
  // upper bound of the maximal one) is wider than the model's diagonal, and the sphere of that
  // radius holds no point of the faces (the certification's query), the gap is open: nothing
  // nearer than the model is large. A point it finds (a wall narrower than s1's spacing, or one
  // s1 misses) starts the solve instead.
  int startFace = -1;
  real startU = 0, startV = 0;
  if (hinted)
  {
    startFace = hint->face;
    startU = hint->u;
    startV = hint->v;
  }
  else if (best >= 0)
  {
    startFace = s1_face(s1Face, best);
    startU = s1UV[2 * best];
    startV = s1UV[2 * best + 1];
  }
  const int started = hinted || best >= 0;
  // Across a thin wall, the point of the face across nearest to O (wall_partner_start).
  const int partner = started && !(m->mode & MODE_EXTERIOR) &&
    wall_partner_start(m, ownFace, Ohi, Olo, d, &t, &startFace, &startU, &startV);
  if ((m->mode & MODE_EXTERIOR) && (!started || !(t < scale)))
  {
    PointInside inside;
    if (!find_point_inside(m, ownFace, Ohi, Olo, d, scale, check_depth(m, scale), &inside))
    {
      r.reason = FAIL_NO_OPPOSITE;
      return r;
    }
    if (!started)
    {
      startFace = inside.face;
      startU = inside.u;
      startV = inside.v;
      t = inside.t;
    }
  }
  else if (!started)
  {
    r.reason = FAIL_NO_OPPOSITE;
    return r;
  }
  const int fromCertification = !started;
  const real firstT = t;
  if (selfContact && !fromCertification && !partner && same_exact_surface(m, startFace, ownFace))
  {
    // The start lies on O's own surface, on another face of it (a rod or a ball split into
    // halves): the sphere touching that surface across is the closed form's, and it touches the
    // start's face along a circle, where eq. 4's Newton is singular (in float it fails on most
    // such samples and the descents after it stray). That sphere, its foot the circle's point
    // next to the start, is the candidate; the checks below decide as for any other.
    __global const real* e = m->faceDomain + FACE_REALS * ownFace + FACE_EXACT;
    const real3 near = hinted ? hintW
                              : make_real3(s1Point[3 * best], s1Point[3 * best + 1],
                                  s1Point[3 * best + 2]) - O;
    real3 foot;
    real u = startU, v = startV;
    int patch;
    if (self_contact_foot(faceInfo[FACE_INTS * ownFace + 8], e, -anchor_minus(e, Ohi, Olo), d,
          tSelf, near, &foot) &&
      project_on_face(m, startFace, Ohi, Olo, foot, 1, &u, &v, &patch))
    {
      r.type = CONTACT_SURFACE_SURFACE;
      r.face = startFace;
      r.patch = patch;
      r.param = make_real2(u, v);
      r.foot = foot;
      // The closed form's radius, which the exact finish reports: the clearance's eq. 1 at the
      // foot across would make it larger by half the clearance, and the patches there, within
      // their accuracy of the surface, would reach into it by more than the checks allow.
      r.t = tSelf;
    }
  }
  if (r.type == CONTACT_FAILED)
    r = solve_from(m, ownFace, Ohi, Olo, d, startFace, startU, startV, t, scale, stepTol,
      newtonTol, maxIterations, maxEdgeIterations, iterations);
  if (r.type == CONTACT_FAILED && r.face >= 0)
  {
    // That start led nowhere: try the best start on any other face once.
    best = initialise(s1Point, s1Face, faceInfo, nodeBox, nodeInfo, O, d, solid, r.face, scale,
      REAL_MAX, m->delta, 0, &t);
    if (best >= 0)
    {
      const Result other = solve_from(m, ownFace, Ohi, Olo, d, s1_face(s1Face, best),
        s1UV[2 * best], s1UV[2 * best + 1], t, scale, stepTol, newtonTol, maxIterations,
        maxEdgeIterations, iterations);
      if (other.type != CONTACT_FAILED)
        r = other;
    }
  }
  if (r.type == CONTACT_FAILED)
  {
    // Newton found no sphere from the best starts: descend on t from the best start, and on
    // the face across the edge nearest O; keep the smaller valid sphere (verified below).
    const Result a = descend(m, ownFace, startFace, Ohi, Olo, d, startU, startV, scale, newtonTol,
      maxIterations, maxEdgeIterations, iterations);
    const Result b = descend_across_nearest_edge(m, ownFace, ownUV, Ohi, Olo, d,
      scale, newtonTol, maxIterations, maxEdgeIterations, iterations);
    if (b.type != CONTACT_FAILED && (a.type == CONTACT_FAILED || b.t < a.t))
      r = b;
    else if (a.type != CONTACT_FAILED)
      r = a;
    if (r.type == CONTACT_FAILED)
    {
      // No Newton or descent converged (a wall touched along an arc, a start the Newtons cycle
      // around): the shrinking ball instead, from eq. 1's sphere over s1 (an upper bound of the
      // maximal one: it holds no s1 point deeper than the clearance), or for the gap whose start
      // came from the certification (no s1 point in front), from the sphere of the model's
      // diagonal that found it.
      Result s = no_result();
      s.t = fromCertification ? scale : firstT;
      if (shrink_ball(m, ownFace, Ohi, Olo, d, check_depth(m, scale), 0, 0, &s))
        r = s;
      else if (s.touchedOutside)
        r.reason = FAIL_LEFT_MODEL; // (the ball's contact touched from outside)
    }
  }
  // Points inside by less than the patches' accuracy (slack) prove nothing, whatever the
  // clearance.
  const real depth = check_depth(m, scale);
  for (int check = 0; r.type != CONTACT_FAILED; ++check)
  {
    best = verify_s1(m, s1Point, s1Face, nodeBox, nodeInfo, O, d, solid, scale, r.t, depth, &t);
    int inFace;
    real inU, inV;
    // The certification's answer for r's sphere, where it was asked (the else branch); r does
    // not change until the restart's sphere replaces it, so the last resort reuses it.
    PointInside inside;
    int askedInside = 0;
    if (best >= 0)
    {
      inFace = s1_face(s1Face, best);
      inU = s1UV[2 * best];
      inV = s1UV[2 * best + 1];
    }
    else
    {
      // No s1 point inside: maximal at the resolution of s1. The second look decides between
      // the contacts of one sphere at an edge or vertex next to the contact.
      second_look_near(m, ownFace, Ohi, Olo, d, scale, stepTol, newtonTol, maxIterations,
        maxEdgeIterations, iterations, &r);
      // Then the patches themselves: a wall narrower than s1's spacing can still reach in.
      if (!find_point_inside(m, ownFace, Ohi, Olo, d, r.t, depth, &inside))
        break;
      askedInside = 1;
      inFace = inside.face;
      inU = inside.u;
      inV = inside.v;
      t = inside.t;
    }
    // A point inside proves the true radius is below t(best) < r.t: restart, and the restart
    // must shrink the sphere.
    Result again = no_result();
    if (check < 3)
      again = solve_from(m, ownFace, Ohi, Olo, d, inFace, inU, inV, t, scale, stepTol, newtonTol,
        maxIterations, maxEdgeIterations, iterations);
    if (check < 3 && (again.type == CONTACT_FAILED || !(again.t < r.t * (real)(1.0 - 1e-6))))
    {
      // Newton went back to the same sphere or failed: descend on t from the point inside,
      // else on the face across the edge nearest O.
      again = descend(m, ownFace, inFace, Ohi, Olo, d, inU, inV, scale, newtonTol, maxIterations,
        maxEdgeIterations, iterations);
      if (again.type == CONTACT_FAILED || !(again.t < r.t * (real)(1.0 - 1e-6)))
      {
        const Result across = descend_across_nearest_edge(m, ownFace, ownUV, Ohi, Olo,
          d, scale, newtonTol, maxIterations, maxEdgeIterations, iterations);
        if (across.type != CONTACT_FAILED)
          again = across;
      }
    }
    if (check == 3 || again.type == CONTACT_FAILED || !(again.t < r.t * (real)(1.0 - 1e-6)))
    {
      // No Newton or descent shrinks the sphere from the point inside: shrink it through the
      // deepest point of the faces instead (the shrinking ball), then check s1 once more.
      if (settle_not_maximal(m, s1Point, s1Face, s1UV, nodeBox, nodeInfo, ownFace, Ohi, Olo,
            d, scale, newtonTol, maxIterations, maxEdgeIterations, iterations,
            askedInside ? &inside : 0, &r))
      {
        // The shrinking ball stops where no point lies deeper than the certification's depth:
        // where the sphere meets the surface at a grazing angle (an edge or face next to O, as
        // on a thread's flank), that leaves it larger than the tangent one by up to that depth
        // over 1 - cos of the angle at the centre between O and the point. Its contact's own
        // Newton from the ball's foot (polish_result: eq. 4 on its face, or the minimum of
        // eq. 1 along its edge) makes it tangent; kept where it shrinks the sphere, which then
        // lies inside the one certified.
        Result p = r;
        if (polish_result(m, ownFace, Ohi, Olo, d, scale, stepTol, newtonTol, maxIterations,
              maxEdgeIterations, iterations, &p) &&
          sphere_radius(d, p.foot, (real)0) < sphere_radius(d, r.foot, (real)0))
          r = p;
        break;
      }
      r.type = CONTACT_FAILED;
      r.reason = r.touchedOutside ? FAIL_LEFT_MODEL : FAIL_NOT_MAXIMAL;
      r.patch = -1;
      r.edge = -1;
      break;
    }
    r = again;
  }
  return r;
}

// One result in the output layout (OUT_REALS, OUT_INTS): the reported radius is eq. 1's t(P) at
// the foot point the clearance selected.
void write_result(const Result* r, real3 d, int iterations, int exactPass, __global real* oR,
  __global int* oI)
{
  oR[0] = r->type == CONTACT_OSCULATING ? r->t
    : r->type != CONTACT_FAILED && r->type != CONTACT_OTHER_SOLID
    ? sphere_radius(d, r->foot, (real)0)
    : (real)0;
  oR[1] = r->foot.x;
  oR[2] = r->foot.y;
  oR[3] = r->foot.z;
  oR[4] = r->res;
  oR[5] = r->param.x;
  oR[6] = r->param.y;
  oI[0] = r->type;
  oI[1] = r->reason;
  oI[2] = r->face;
  oI[3] = r->patch;
  oI[4] = r->edge;
  oI[5] = iterations;
  oI[6] = exactPass;
}

// The last resort of a sample on a cylinder, cone, sphere or torus whose solve failed or fell short:
// the sphere of radius t that touches its own surface across (self_contact_radius). A ball is
// the case: its maximal sphere is the ball and touches every s1 point, which no restart settles
// (NotMaximal). Kept when no s1 point and no point of the faces lies inside it deeper than the
// patches' accuracy or the clearance (the verification's and the certification's tests), with
// the foot across from O; where the solve failed (alongArc), with the foot round the circle of
// contact on the face where the point across is not on it.
BRT_SPLIT void self_contact_sphere(const Model* m, __global const real* s1Point, __global const int* s1Face,
  __global const real* nodeBox, __global const int* nodeInfo, int ownFace, real2 ownUV, real3 Ohi,
  real3 Olo, real3 d, real scale, real t, int alongArc, Result* r)
{
  const int kind = m->faceInfo[FACE_INTS * ownFace + 8];
  const real depth = check_depth(m, scale);
  real tt;
  if (verify_s1(m, s1Point, s1Face, nodeBox, nodeInfo, Ohi + Olo, d, scope_solid(m, ownFace),
        scale, t, depth, &tt) >= 0)
    return;
  PointInside inside;
  if (find_point_inside(m, ownFace, Ohi, Olo, d, t, depth, &inside))
    return;
  // The foot: across from O through the axis, centre or core circle; its (u, v) from O's moved by
  // half a period (OpenCASCADE's angles: a sphere's longitude and latitude, a cylinder's angle, a
  // torus's angle around its tube).
  __global const real* fd = m->faceDomain + FACE_REALS * ownFace;
  real u = ownUV.x, v = ownUV.y;
  if (kind == EXACT_TORUS && fd[5] > (real)0)
    v = wrap_param(v + (real)0.5 * fd[5], fd[2], fd[5]);
  else if (fd[4] > (real)0)
  {
    u = wrap_param(u + (real)0.5 * fd[4], fd[0], fd[4]);
    if (kind == EXACT_SPHERE)
      v = -v;
  }
  u = clamp(u, fd[0], fd[1]);
  v = clamp(v, fd[2], fd[3]);
  real3 foot = (real)2 * t * d;
  if (kind == EXACT_CONE)
  {
    // Across the axis on the circle through O: with O - the centre = za a + r0, the centre + za a
    // - r0, which is O + 2 (t d + za a).
    const real3 a = make_real3(fd[FACE_EXACT + 6], fd[FACE_EXACT + 7], fd[FACE_EXACT + 8]);
    const real za = dot(-t * d, a);
    foot = (real)2 * (t * d + za * a);
  }
  int patch;
  // The band counts: across from a sample on the far side of a seam, the foot lies on the seam.
  if (!project_on_face(m, ownFace, Ohi, Olo, foot, 1, &u, &v, &patch))
  {
    // A face that holds only part of the circle along which the sphere touches its surface (a
    // round that is a quarter or a half of a tube: the point across lies on the next face): the
    // point of that circle on the face farthest round from O, stepping round from O by eighths
    // of a half-turn either way, each projected from the last. At least a quarter-turn round, so
    // that the face bounds the sphere: a point that far round lies at least (1 - cos 45 deg),
    // 0.29, of any growth of the radius inside the larger sphere. The checks above passed at t.
    // Only where the solve failed: where it found a smaller sphere touching the same surface, a
    // face next to the round that enters the closed form's sphere less than the clearance deep
    // bounds the true one (the engine block's samples 46683 and 46686: OpenCASCADE's bisection
    // agrees with the solve to six digits, 0.987831, the closed form 1 holds that face 2.3e-4
    // deep).
    if (!alongArc || (kind != EXACT_CYLINDER && kind != EXACT_TORUS))
      return;
    __global const real* e = fd + FACE_EXACT;
    const real3 a = make_real3(e[6], e[7], e[8]);
    // The circle's plane: across the axis for a cylinder, the meridian plane for a torus.
    const real3 across = kind == EXACT_CYLINDER ? cross(a, d) : a - dot(a, d) * d;
    if (!(length(across) > (real)1e-6))
      return;
    const real3 side = normalize(across);
    int reached = 0;
    for (int sense = -1; sense <= 1; sense += 2)
    {
      real uu = ownUV.x, vv = ownUV.y;
      int pp;
      for (int k = 1; k <= 8; ++k)
      {
        const real theta = (real)k * (real)0.39269908169872414; // k pi / 8
        const real3 f = t * ((real)1 - cos(theta)) * d + (real)sense * t * sin(theta) * side;
        if (!project_on_face(m, ownFace, Ohi, Olo, f, 1, &uu, &vv, &pp))
          break;
        if (k > reached)
        {
          reached = k;
          foot = f;
          u = uu;
          v = vv;
          patch = pp;
        }
      }
    }
    if (reached < 2)
      return;
  }
  *r = no_result();
  r->type = CONTACT_SURFACE_SURFACE;
  r->face = ownFace;
  r->patch = patch;
  r->param = make_real2(u, v);
  r->foot = foot;
  r->t = t;
}

// The osculating bound (docs/Solver.md, "Osculating spheres"): no sphere tangent at O lies in
// the material beyond radius 1 / kappa, kappa the largest curvature of O's own face at O towards
// d (of the exact surface: the reader's, carried with the sample). Where the solve's sphere is
// larger than that, or the solve failed at a sphere that touches only next to O (LeftModel,
// NotMaximal, a Newton that did not converge), the sphere of radius 1 / kappa tangent at O is
// the maximal one when nothing lies in it deeper than the checks' depth (the verification's and
// the certification's tests, as self_contact_sphere's): it touches O's own face at O itself to
// second order (CONTACT_OSCULATING, the foot at O). Where something does, a sphere the solve
// found larger than the bound fails NotMaximal: it is not the maximal sphere, and the one inside
// the bound was not found. A sphere the solve found and certified holds the osculating one (both
// tangent at O, along d), so nothing lies deeper in that one than the checks allowed in its own:
// the checks run only where the solve failed or certified nothing. Points of O's own face next to
// O may lie in the osculating sphere less deep than the checks see, a quarter of its radius from
// O changing eq. 1's radius by 16 times their depth: where the solve's contact was on O's own
// face, descents of eq. 1 over that face (descend) from the two points that far from O along its
// more curved parameter take a contact away from O whose radius is smaller by more than the
// patches' accuracy (on a cylinder's round every point of the arc is such a contact to within
// it).
BRT_SPLIT void osculating_bound(const Model* m, __global const real* s1Point,
  __global const int* s1Face, __global const real* nodeBox, __global const int* nodeInfo,
  int ownFace, real2 ownUV, real3 Ohi, real3 Olo, real3 d, real scale, real newtonTol,
  int maxIterations, int maxEdgeIterations, real kappa, int* iterations, Result* r)
{
  if (!(kappa > (real)0) || r->type == CONTACT_OTHER_SOLID || r->type == CONTACT_OSCULATING)
    return;
  const real t = (real)1 / kappa;
  if (r->type == CONTACT_FAILED)
  {
    if (r->reason != FAIL_LEFT_MODEL && r->reason != FAIL_NOT_MAXIMAL &&
      r->reason != FAIL_NOT_CONVERGED && r->reason != FAIL_EDGE_NOT_CONVERGED &&
      r->reason != FAIL_SINGULAR)
      return;
    if (!(t < scale))
      return;
  }
  else if (!(sphere_radius(d, r->foot, (real)0) * kappa > (real)1 + (real)1e-5))
    return;
  const int ownContact = r->type == CONTACT_SURFACE_SURFACE && r->face == ownFace;
  const real depth = check_depth(m, scale);
  real tt;
  PointInside inside;
  if ((r->type == CONTACT_FAILED || !(m->mode & MODE_CERTIFY)) &&
    (verify_s1(m, s1Point, s1Face, nodeBox, nodeInfo, Ohi + Olo, d, scope_solid(m, ownFace),
       scale, t, depth, &tt) >= 0 ||
      find_point_inside(m, ownFace, Ohi, Olo, d, t, depth, &inside)))
  {
    if (r->type != CONTACT_FAILED)
    {
      r->type = CONTACT_FAILED;
      r->reason = FAIL_NOT_MAXIMAL;
    }
    return;
  }
  const int patch = find_patch(m, ownFace, ownUV.x, ownUV.y);
  *r = no_result();
  r->type = CONTACT_OSCULATING;
  r->face = ownFace;
  r->patch = patch;
  r->param = ownUV;
  r->foot = make_real3((real)0, (real)0, (real)0);
  r->t = t;
  if (!ownContact)
    return;
  const PatchEval e = eval_patch(m, patch, ownUV.x, ownUV.y);
  const real lu = length(e.Du), lv = length(e.Dv);
  if (!(lu > (real)0) || !(lv > (real)0))
    return;
  // The more curved parameter: the larger |S_uu . d| / |S_u|^2 (the patches' curvature is off
  // by percents, its direction is not).
  const int alongU = fabs(dot(e.Duu, d)) * lv * lv >= fabs(dot(e.Dvv, d)) * lu * lu;
  real best = t - m->slack;
  for (int k = 0; k < 2; ++k)
  {
    const real step = (real)0.25 * t * (k ? (real)-1 : (real)1);
    const real u = ownUV.x + (alongU ? step / lu : (real)0);
    const real v = ownUV.y + (alongU ? (real)0 : step / lv);
    const Result c = descend(m, ownFace, ownFace, Ohi, Olo, d, u, v, scale, newtonTol,
      maxIterations, maxEdgeIterations, iterations);
    if (c.type == CONTACT_FAILED)
      continue;
    const real tc = sphere_radius(d, c.foot, (real)0);
    if (tc < best)
    {
      best = tc;
      *r = c;
    }
  }
}

// A float solve's osculating sphere checked again in this precision (brt_finish on the device,
// NativeSolver::Polish on the host): the bound from a failed result, so that the checks run at
// this precision's radius; failed NotMaximal where they find something.
BRT_SPLIT void recheck_osculating(const Model* m, __global const real* s1Point,
  __global const int* s1Face, __global const real* nodeBox, __global const int* nodeInfo,
  int ownFace, real2 ownUV, real3 Ohi, real3 Olo, real3 d, real scale, real newtonTol,
  int maxIterations, int maxEdgeIterations, real kappa, int* iterations, Result* r)
{
  *r = no_result();
  r->type = CONTACT_FAILED;
  r->reason = FAIL_NOT_MAXIMAL;
  osculating_bound(m, s1Point, s1Face, nodeBox, nodeInfo, ownFace, ownUV, Ohi, Olo, d, scale,
    newtonTol, maxIterations, maxEdgeIterations, kappa, iterations, r);
}

// An empty memo, for a chain's start (solve_chain).
inline void memo_clear(ChainMemo* memo)
{
  for (int k = 0; k < MEMO_DISKS; ++k)
  {
    memo->face[k] = -1;
    memo->u[k] = memo->v[k] = memo->r[k] = memo->gap[k] = (real)0;
  }
  memo->next = 0;
  memo->ownFace = -1;
  memo->ownU = memo->ownV = (real)0;
}

// O's (u, v) on its face for the certification (certify_patch), where the face's patches are its
// surface and the sample's (u, v) gives O there within the patches' accuracy; else none.
inline void memo_own_point(const Model* m, ChainMemo* memo, int ownFace, real2 ownUV, real3 Ohi,
  real3 Olo)
{
  memo->ownFace = -1;
  if (ownFace < 0 || !m->faceInfo[FACE_INTS * ownFace + 10])
    return;
  const int p = find_patch(m, ownFace, ownUV.x, ownUV.y);
  const real3 w =
    eval_patch_point(m, p, ownUV.x, ownUV.y) + anchor_minus(m->patchAnchor + 6 * p, Ohi, Olo);
  if (!(dot(w, w) <= m->slack * m->slack))
    return;
  memo->ownFace = ownFace;
  memo->ownU = ownUV.x;
  memo->ownV = ownUV.y;
}

// The whole solve of one sample (the kernel's work-item; the native device's loop body): sp is
// the sample's SAMPLE_REALS, oR and oI its OUT_REALS and OUT_INTS.
BRT_SPLIT void solve_sample(Model mm, __global const real* s1Point, __global const int* s1Face,
  __global const real* s1UV, __global const real* nodeBox, __global const int* nodeInfo,
  __global const real* sp, int ownFace, real scale, real stepTol, real newtonTol,
  int maxIterations, int maxEdgeIterations, Hint* hint, __global real* oR, __global int* oI)
{
  const real clearance = mm.delta;
  const real3 Ohi = make_real3(sp[0], sp[1], sp[2]), Olo = make_real3(sp[3], sp[4], sp[5]);
  const real3 d = make_real3(sp[6], sp[7], sp[8]);
  const real2 ownUV = make_real2(sp[9], sp[10]);
  int iterations = 0, exactPass = 0;
  if (mm.memo)
    memo_own_point(&mm, mm.memo, ownFace, ownUV, Ohi, Olo);
  if ((mm.mode & MODE_EXTERIOR) && (mm.mode & MODE_ALL_SOLIDS))
  {
    // The gap with all solids: where another solid touches or overlaps O's, the gap is 0.
    int other;
    if (inside_other_solid(&mm, ownFace, Ohi, Olo, d, scale, &other))
    {
      Result c = no_result();
      c.type = CONTACT_OTHER_SOLID;
      c.face = other;
      write_result(&c, d, 0, 0, oR, oI);
      return;
    }
  }
  Result r = solve_with_clearance(&mm, s1Point, s1Face, s1UV, nodeBox, nodeInfo, ownFace, ownUV,
    Ohi, Olo, d, scale, stepTol, newtonTol, maxIterations, maxEdgeIterations, hint, &iterations);
  Hint none;
  none.face = -1;
  none.u = none.v = (real)0;
  if (r.type == CONTACT_FAILED && hint->face >= 0)
  {
    // Failed from the chain's start (a start across the wrong wall, whose restarts could not
    // shrink the sphere): solved again from s1, as without chains, so that a chain fails no
    // sample the start from s1 solves.
    r = solve_with_clearance(&mm, s1Point, s1Face, s1UV, nodeBox, nodeInfo, ownFace, ownUV, Ohi,
      Olo, d, scale, stepTol, newtonTol, maxIterations, maxEdgeIterations, &none, &iterations);
  }
  if (r.type == CONTACT_FAILED && clearance > (real)0)
  {
    // Failed with the clearance (next to an acute convex edge, say): solve without it
    //.
    mm.delta = 0;
    const Result exact = solve_with_clearance(&mm, s1Point, s1Face, s1UV, nodeBox, nodeInfo,
      ownFace, ownUV, Ohi, Olo, d, scale, stepTol, newtonTol, maxIterations, maxEdgeIterations,
      &none, &iterations);
    if (exact.type != CONTACT_FAILED)
    {
      r = exact;
      exactPass = 1;
    }
  }
  if (!(mm.mode & MODE_EXTERIOR))
  {
    // A sphere touching O's own cylinder, cone, sphere or torus across: the closed form where the solve
    // failed, or fell short of it (a ball's spheres touch every point: in float the solve may stop
    // on a foot next to O).
    const int kind = mm.faceInfo[FACE_INTS * ownFace + 8];
    __global const real* e = mm.faceDomain + FACE_REALS * ownFace + FACE_EXACT;
    real tc;
    if (self_contact_radius(kind, e, -anchor_minus(e, Ohi, Olo), d, mm.slack, &tc) &&
      (r.type == CONTACT_FAILED ||
        (same_exact_surface(&mm, r.face, ownFace) && r.t < tc - (real)0.5 * mm.slack)))
    {
      Result c = no_result();
      self_contact_sphere(&mm, s1Point, s1Face, nodeBox, nodeInfo, ownFace, ownUV, Ohi, Olo, d,
        scale, tc, r.type == CONTACT_FAILED, &c);
      if (c.type != CONTACT_FAILED)
        r = c;
    }
  }
  exact_finish(&mm, ownFace, Ohi, Olo, d, stepTol, &r);
  reject_contact_from_outside(&mm, ownFace, Ohi, Olo, d, scale, &r);
  const Result found = r;
  osculating_bound(&mm, s1Point, s1Face, nodeBox, nodeInfo, ownFace, ownUV, Ohi, Olo, d, scale,
    newtonTol, maxIterations, maxEdgeIterations, sp[11], &iterations, &r);
  flag_thin_wall(&mm, ownFace, Ohi, Olo, d, scale, &r);
  write_result(&r, d, iterations, exactPass, oR, oI);
  // The next sample of the chain starts from this one's contact across: its point on the face,
  // or for an edge or vertex contact, the edge's point on the edge's first face (where the
  // previous sample's edge contact is the next one's too, eq. 4 from there runs onto the edge).
  // An osculating sphere has none: the contact the solve found before the bound, where it found
  // one (the next sample along a round is likely bounded by the same face again).
  const Result h = r.type == CONTACT_OSCULATING ? found : r;
  hint->face = h.type == CONTACT_SURFACE_SURFACE ? h.face : -1;
  hint->u = h.param.x;
  hint->v = h.param.y;
  if ((h.type == CONTACT_SURFACE_EDGE || h.type == CONTACT_SURFACE_VERTEX) && h.edge >= 0)
  {
    const int f0 = mm.edgeInfo[4 * h.edge + 2];
    real u, v;
    if (f0 >= 0 && edge_point_on_face(&mm, f0, h.edge, h.param.x, &u, &v))
    {
      hint->face = f0;
      hint->u = u;
      hint->v = v;
    }
  }
}

// A chain: n samples of one face (SAMPLE_REALS each, neighbours in SpatialOrder) solved in turn,
// each after the first started from the one before it (Hint); results in OUT_REALS and OUT_INTS
// per sample. The host cuts the chains (brt::ChainStarts) from the samples' order alone, so every
// device and thread count solves each sample from the same start (docs/Solver.md, item 20,
// "Chains").
void solve_chain(Model mm, __global const real* s1Point, __global const int* s1Face,
  __global const real* s1UV, __global const real* nodeBox, __global const int* nodeInfo,
  __global const real* sp, __global const int* faces, int n, real scale, real stepTol,
  real newtonTol, int maxIterations, int maxEdgeIterations, __global real* oR, __global int* oI)
{
  Hint hint;
  hint.face = -1;
  hint.u = hint.v = (real)0;
  ChainMemo memo;
  memo_clear(&memo);
  mm.memo = &memo;
  for (int k = 0; k < n; ++k)
    solve_sample(mm, s1Point, s1Face, s1UV, nodeBox, nodeInfo, sp + SAMPLE_REALS * k, faces[k],
      scale, stepTol, newtonTol, maxIterations, maxEdgeIterations, &hint, oR + OUT_REALS * k,
      oI + OUT_INTS * k);
}

#ifdef __OPENCL_VERSION__
// The model's buffers, kernel arguments 0..32 of every kernel (brt::KernelModel, in this order).
#define MODEL_PARAMS                                                                             \
  __global const real *patches, __global const real *patchAnchor,                                \
    __global const real *patchDomain, __global const int *faceInfo,                             \
    __global const real *faceDomain, __global const real *breaks, __global const int *loops,     \
    __global const real *trim, __global const int *trimEdge, __global const real *trimRange,     \
    __global const int *edgeInfo, __global const real *edgeRange, __global const real *edgeSeg,  \
    __global const real *edgeAnchor, __global const real *edgeSegRange,                         \
    __global const real *s1Point, __global const int *s1Face, __global const real *s1UV,         \
    __global const real *nodeBox, __global const int *nodeInfo, __global const int *vertexInfo,  \
    __global const int *patchFace, __global const int *edgeSegEdge,                              \
    __global const real *patchBoxes, __global const real *edgeBoxes,                             \
    __global const real *boxNodeBox, __global const int *boxNodeInfo,                           \
    __global const int *boxItems, __global const real *trimNodeBox,                              \
    __global const int *trimNodeInfo, __global const int *trimItems,                             \
    __global const real *patchSector, __global const real *patchHull
// Then the launch's: the samples (SAMPLE_REALS each) and their faces, the count, the scalars
// (brt::KernelScalars), arguments 33..45.
#define LAUNCH_PARAMS                                                                            \
  __global const real *samples, __global const int *sampleFace, const int count,                \
    const real scale, const real stepTol, const real newtonTol, const real slack,                \
    const real clearance, const int maxIterations, const int maxEdgeIterations,                 \
    const real s1Spacing, const int patchCount, const int mode
#define MODEL_INIT                                                                               \
  { patches, patchAnchor, patchDomain, faceInfo, faceDomain, breaks, loops, trim, trimEdge,      \
    trimRange, trimNodeBox, trimNodeInfo, trimItems, edgeInfo, edgeRange, edgeSeg, edgeAnchor,   \
    edgeSegRange, vertexInfo, slack,                                                             \
    clearance, s1Spacing, patchFace, edgeSegEdge, patchBoxes, patchSector, patchHull, edgeBoxes, \
    boxNodeBox, boxNodeInfo, boxItems, patchCount, mode, 0 }

// The solve: one work-item per chain (solve_chain; brt::ChainStarts), chain k the samples
// [chainFirst[k], chainFirst[k + 1]); results in OUT_REALS and OUT_INTS per sample (arguments
// 46, 47; the chains 48 and their count 49).
__kernel void brt_solve(MODEL_PARAMS, LAUNCH_PARAMS, __global real* outReal, __global int* outInt,
  __global const int* chainFirst, const int chains)
{
  const int gid = get_global_id(0);
  if (gid >= chains)
    return;
  const Model mm = MODEL_INIT;
  const int first = chainFirst[gid];
  solve_chain(mm, s1Point, s1Face, s1UV, nodeBox, nodeInfo, samples + SAMPLE_REALS * first,
    sampleFace + first, chainFirst[gid + 1] - first, scale, stepTol, newtonTol, maxIterations,
    maxEdgeIterations, outReal + OUT_REALS * first, outInt + OUT_INTS * first);
}

// The ray thickness (ray_thickness): one work-item per sample; the distance in outRay (REAL_MAX
// where the ray meets nothing) and the face hit in outFace (-1) (arguments 46, 47). Needs the
// certification's boxes (MODE_CERTIFY).
__kernel void brt_ray(MODEL_PARAMS, LAUNCH_PARAMS, __global real* outRay, __global int* outFace)
{
  const int gid = get_global_id(0);
  if (gid >= count)
    return;
  const Model mm = MODEL_INIT;
  __global const real* sp = samples + SAMPLE_REALS * gid;
  int face = -1;
  outRay[gid] = ray_thickness(&mm, sampleFace[gid], make_real3(sp[0], sp[1], sp[2]),
    make_real3(sp[3], sp[4], sp[5]), make_real3(sp[6], sp[7], sp[8]), stepTol, &face);
  outFace[gid] = face;
}

#ifdef BRT_DOUBLE
// The float solve's finish on the device, in double (built in the double program of a device
// with cl_khr_fp64): each float contact polished (polish_result) and certified again; the
// results in double in outReal/outInt, and redo[gid] = 1 where the sample must be solved again
// in double (the float solve failed it, or its sphere holds boundary). Arguments 46..50.
__kernel void brt_finish(MODEL_PARAMS, LAUNCH_PARAMS, __global const float* floatReal,
  __global const int* floatInt, __global real* outReal, __global int* outInt, __global int* redo)
{
  const int gid = get_global_id(0);
  if (gid >= count)
    return;
  __global const real* sp = samples + SAMPLE_REALS * gid;
  __global const float* fR = floatReal + OUT_REALS * gid;
  __global const int* fI = floatInt + OUT_INTS * gid;
  __global real* oR = outReal + OUT_REALS * gid;
  __global int* oI = outInt + OUT_INTS * gid;
  const int ownFace = sampleFace[gid];
  Model mm = MODEL_INIT;
  if (fI[6])
    mm.delta = 0; // found by the pass without clearance
  const real3 Ohi = make_real3(sp[0], sp[1], sp[2]), Olo = make_real3(sp[3], sp[4], sp[5]);
  const real3 d = make_real3(sp[6], sp[7], sp[8]);
  Result r = no_result();
  r.type = fI[0];
  r.reason = fI[1];
  r.face = fI[2];
  r.patch = fI[3];
  r.edge = fI[4];
  r.res = fR[4];
  r.foot = make_real3(fR[1], fR[2], fR[3]);
  r.param = make_real2(fR[5], fR[6]);
  r.t = sphere_radius(d, r.foot, mm.delta);
  int iterations = fI[5], again = r.type == CONTACT_FAILED;
  if (r.type == CONTACT_OSCULATING)
  {
    recheck_osculating(&mm, s1Point, s1Face, nodeBox, nodeInfo, ownFace, make_real2(sp[9], sp[10]),
      Ohi, Olo, d, scale, newtonTol, maxIterations, maxEdgeIterations, sp[11], &iterations, &r);
    again = r.type == CONTACT_FAILED;
  }
  else if (!again && r.type != CONTACT_OTHER_SOLID)
  {
    polish_result(&mm, ownFace, Ohi, Olo, d, scale, stepTol, newtonTol, maxIterations,
      maxEdgeIterations, &iterations, &r);
    PointInside inside;
    again = find_point_inside(&mm, ownFace, Ohi, Olo, d, sphere_radius(d, r.foot, (real)0),
      fmax(mm.delta, mm.slack), &inside);
    exact_finish(&mm, ownFace, Ohi, Olo, d, stepTol, &r);
    reject_contact_from_outside(&mm, ownFace, Ohi, Olo, d, scale, &r);
    again = again || r.type == CONTACT_FAILED;
  }
  // (A wall across thinner than the float pass could tell: failed here, not solved again.)
  flag_thin_wall(&mm, ownFace, Ohi, Olo, d, scale, &r);
  if (r.reason == FAIL_THIN_WALL)
    again = 0;
  write_result(&r, d, iterations, fI[6], oR, oI);
  redo[gid] = again;
}
#endif
#endif
