// The convex hull of a mesh's vertices, as MuJoCo 2.2.2 builds it for collision (mjCMesh::MakeGraph):
// qhull (Debian's libqhull_r, the library MuJoCo runs) with option Qt, its facets triangulated and
// each vertex's facets listed; the graph then records, per hull vertex in qhull's vertex order, the
// distinct other vertices of its facets in qhull's facet and vertex order. The collision's support
// function climbs this graph, so the order decides which vertex a tie goes to: it is qhull's.
#include <csetjmp>
#include <cstdio>
#include <string>
#include <vector>

#include "mesh.hpp"

#ifdef LEVER_HAVE_QHULL
extern "C" {
#include <libqhull_r/qhull_ra.h>
}
#endif

namespace lever::mjcf::detail {

#ifdef LEVER_HAVE_QHULL

namespace {

// The graph's parts, written by run_qhull as qhull hands them out.
struct HullParts {
  int numvert = 0, numface = 0;
  std::vector<int> vertex_index;          // per hull vertex: its mesh vertex
  std::vector<int> edge_address;          // per hull vertex: its first neighbour in `neighbours`
  std::vector<int> neighbours;            // mesh vertex numbers for now, each list ended by -1
  std::vector<int> triangles;             // three mesh vertices per facet, outward
  bool points_in_range = true;
  bool triangles_only = true;
};

// qhull reports errors by longjmp to the setjmp below, so this frame holds nothing that needs a
// destructor: the vectors it fills are the caller's. Returns qhull's exit code (0: success).
int run_qhull(double* points, int count, HullParts& parts) {
  qhT qh_qh;
  qhT* qh = &qh_qh;
  QHULL_LIB_CHECK
  qh_zero(qh, stderr);
  qh_init_A(qh, stdin, stdout, stderr, 0, nullptr);
  char options[] = "qhull Qt";
  const int code = setjmp(qh->errexit);
  if (code == 0) {
    qh->NOerrexit = False;
    qh_initflags(qh, options);
    qh_init_B(qh, points, count, 3, False);
    qh_qhull(qh);
    qh_triangulate(qh);
    qh_vertexneighbors(qh);

    parts.numvert = qh->num_vertices;
    parts.numface = qh->num_facets;
    vertexT* vertex;
    FORALLvertices {
      const int id = qh_pointid(qh, vertex->point);
      if (id < 0 || id >= count) {
        parts.points_in_range = false;
        break;
      }
      parts.edge_address.push_back(static_cast<int>(parts.neighbours.size()));
      parts.vertex_index.push_back(id);
      const size_t first = parts.neighbours.size();
      facetT* facet;
      facetT** facetp;
      FOREACHsetelement_(facetT, vertex->neighbors, facet) {
        int corners = 0;
        vertexT* other;
        vertexT** otherp;
        FOREACHsetelement_(vertexT, facet->vertices, other) {
          ++corners;
          const int other_id = qh_pointid(qh, other->point);
          if (other_id < 0 || other_id >= count) {
            parts.points_in_range = false;
            break;
          }
          if (other_id == id) continue;
          bool listed = false;
          for (size_t e = first; e < parts.neighbours.size(); ++e) {
            listed = listed || parts.neighbours[e] == other_id;
          }
          if (!listed) parts.neighbours.push_back(other_id);
        }
        if (corners != 3) parts.triangles_only = false;
      }
      parts.neighbours.push_back(-1);
    }

    facetT* facet;
    FORALLfacets {
      // qhull's toporient facets list their vertices the other way round
      const int slot[3] = {facet->toporient ? 1 : 0, facet->toporient ? 0 : 1, 2};
      int corner = 0;
      vertexT* corner_vertex;
      vertexT** corner_vertexp;
      const size_t base = parts.triangles.size();
      parts.triangles.resize(base + 3, -1);
      FOREACHsetelement_(vertexT, facet->vertices, corner_vertex) {
        if (corner >= 3) {
          parts.triangles_only = false;
          break;
        }
        parts.triangles[base + static_cast<size_t>(slot[corner++])] =
            qh_pointid(qh, corner_vertex->point);
      }
    }
  }
  qh->NOerrexit = True;
  int curlong, totlong;
  qh_freeqhull(qh, !qh_ALL);
  qh_memfreeshort(qh, &curlong, &totlong);
  return code;
}

}  // namespace

std::vector<int> convex_hull_graph(const std::vector<float>& vert) {
  const int count = static_cast<int>(vert.size() / 3);
  if (count < 4) return {};  // MuJoCo builds no graph for so few vertices
  std::vector<double> points(vert.begin(), vert.end());
  HullParts parts;
  if (run_qhull(points.data(), count, parts) != 0) {
    throw MeshError("qhull could not build the convex hull of its vertices (MuJoCo: qhull error)");
  }
  if (!parts.points_in_range || !parts.triangles_only ||
      parts.neighbours.size() != static_cast<size_t>(parts.numvert + 3 * parts.numface)) {
    // MuJoCo drops such a graph with a warning (or stops): lever refuses the mesh
    throw MeshError("qhull returned a convex hull MuJoCo 2.2.2 would not use");
  }
  // the graph, with each neighbour as its hull vertex number
  std::vector<int> graph;
  graph.reserve(2 + 3 * static_cast<size_t>(parts.numvert) + 6 * static_cast<size_t>(parts.numface));
  graph.push_back(parts.numvert);
  graph.push_back(parts.numface);
  graph.insert(graph.end(), parts.edge_address.begin(), parts.edge_address.end());
  graph.insert(graph.end(), parts.vertex_index.begin(), parts.vertex_index.end());
  for (const int neighbour : parts.neighbours) {
    if (neighbour < 0) {
      graph.push_back(-1);
      continue;
    }
    int hull_vertex = 0;
    while (parts.vertex_index[static_cast<size_t>(hull_vertex)] != neighbour) ++hull_vertex;
    graph.push_back(hull_vertex);
  }
  graph.insert(graph.end(), parts.triangles.begin(), parts.triangles.end());
  return graph;
}

#else

std::vector<int> convex_hull_graph(const std::vector<float>&) {
  throw MeshError("this build of lever has no qhull, which builds the convex hull for collision");
}

#endif

}  // namespace lever::mjcf::detail
