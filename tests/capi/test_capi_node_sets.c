/* Interfaces on node sets (ffrf_case_add_interface_nodes) against interfaces on surfaces
 * (ffrf_case_add_interface) of the same Tet10 block, same nodes, same virtual nodes: the
 * constrained normal modes must agree (relative, every frequency) for
 *  - uniform RBE3 weights (weights NULL) against FFRF_RBE3: bitwise;
 *  - given weights equal to the tributary area weights, computed here in closed form for the
 *    flat straight-sided Tri6 faces (corners A/12, mid-side nodes A/4 of each triangle),
 *    against FFRF_RBE3_AREA;
 *  - the mid-side nodes alone with weights A/3 of each triangle against
 *    FFRF_RBE3_AREA_CONSISTENT, whose corner weights are 0 on flat Tri6 faces: a corner of
 *    weight 0 is not coupled to the virtual node (docs/input.md "RBE3 weights");
 * the last two to 1e-11, the accuracy of the modal solver (see main). The weights matter: the
 * three weightings give frequencies more than 1e-3 apart.
 * The block: 0.2 x 0.04 x 0.03 m, 5 x 2 x 2 cubes of 6 Tet10 each; RBE3 interfaces on the end
 * faces x = 0 (all six dofs held) and x = 0.2 (free). */
#include <math.h>

#include "check.h"

#define NX 5
#define NY 2
#define NZ 2
#define NC ((NX + 1) * (NY + 1) * (NZ + 1))
#define MAX_NODES 1024
#define NUM_TETS (6 * NX * NY * NZ)
#define NUM_MODES 8

static const double size_[3] = {0.2, 0.04, 0.03};
static double xyz[3 * MAX_NODES];
static int num_nodes = 0, tets[10 * NUM_TETS], edge_node[NC][NC];

static int corner(int i, int j, int k) { return i + (NX + 1) * (j + (NY + 1) * k); }

/* The mid-side node of edge (a, b), made on first use. */
static int mid(int a, int b)
{
    if (edge_node[a][b] < 0) {
        int d;
        for (d = 0; d < 3; d++)
            xyz[3 * num_nodes + d] = 0.5 * (xyz[3 * a + d] + xyz[3 * b + d]);
        edge_node[a][b] = edge_node[b][a] = num_nodes++;
    }
    return edge_node[a][b];
}

/* Kuhn's six tetrahedra per cube (all along the diagonal 0-7: conforming), positively
 * oriented, Tet10 in Gmsh's order (edges 0-1, 1-2, 0-2, 0-3, 2-3, 1-3). */
static void make_block(void)
{
    static const int kuhn[6][4] = {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7},
                                   {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}};
    static const int edges[6][2] = {{0, 1}, {1, 2}, {0, 2}, {0, 3}, {2, 3}, {1, 3}};
    int i, j, k, t, e, n = 0;
    memset(edge_node, -1, sizeof edge_node);
    for (k = 0; k <= NZ; k++)
        for (j = 0; j <= NY; j++)
            for (i = 0; i <= NX; i++) {
                int c = corner(i, j, k);
                xyz[3 * c] = size_[0] * i / NX;
                xyz[3 * c + 1] = size_[1] * j / NY;
                xyz[3 * c + 2] = size_[2] * k / NZ;
            }
    num_nodes = NC;
    for (k = 0; k < NZ; k++)
        for (j = 0; j < NY; j++)
            for (i = 0; i < NX; i++)
                for (t = 0; t < 6; t++) {
                    int v[4], *tet = tets + 10 * n++;
                    double a[3], b[3], c[3], volume;
                    for (e = 0; e < 4; e++) {
                        int bit = kuhn[t][e];
                        v[e] = corner(i + (bit & 1), j + ((bit >> 1) & 1), k + ((bit >> 2) & 1));
                    }
                    for (e = 0; e < 3; e++) {
                        a[e] = xyz[3 * v[1] + e] - xyz[3 * v[0] + e];
                        b[e] = xyz[3 * v[2] + e] - xyz[3 * v[0] + e];
                        c[e] = xyz[3 * v[3] + e] - xyz[3 * v[0] + e];
                    }
                    volume = a[0] * (b[1] * c[2] - b[2] * c[1]) -
                             a[1] * (b[0] * c[2] - b[2] * c[0]) +
                             a[2] * (b[0] * c[1] - b[1] * c[0]);
                    if (volume < 0.0) {
                        int swap = v[1];
                        v[1] = v[2];
                        v[2] = swap;
                    }
                    for (e = 0; e < 4; e++)
                        tet[e] = v[e];
                    for (e = 0; e < 6; e++)
                        tet[4 + e] = mid(v[edges[e][0]], v[edges[e][1]]);
                }
}

/* The Tri6 faces of the block on the plane x = x0 (the tetrahedron faces whose three corners
 * lie on it), their count. */
static int end_faces(double x0, int *tris)
{
    static const int faces[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
    int n = 0, t, f, a;
    for (t = 0; t < NUM_TETS; t++)
        for (f = 0; f < 4; f++) {
            const int *tet = tets + 10 * t;
            int on = 1, *tri = tris + 6 * n;
            for (a = 0; a < 3; a++)
                on = on && fabs(xyz[3 * tet[faces[f][a]]] - x0) < 1e-12;
            if (!on)
                continue;
            for (a = 0; a < 3; a++)
                tri[a] = tet[faces[f][a]];
            tri[3] = mid(tri[0], tri[1]);
            tri[4] = mid(tri[1], tri[2]);
            tri[5] = mid(tri[2], tri[0]);
            n++;
        }
    return n;
}

/* Node set of faces tris[6 x n] (corners too unless corners == 0) and per-node weights:
 * closed-form tributary (corner A/12, mid-side A/4) or consistent (mid-side A/3) areas. */
static int face_nodes(const int *tris, int n, int corners, int consistent, int *nodes,
                      double *weights)
{
    int count = 0, t, a, k;
    for (t = 0; t < n; t++) {
        const int *tri = tris + 6 * t;
        double u[3], v[3], w[3], area;
        for (k = 0; k < 3; k++) {
            u[k] = xyz[3 * tri[1] + k] - xyz[3 * tri[0] + k];
            v[k] = xyz[3 * tri[2] + k] - xyz[3 * tri[0] + k];
        }
        w[0] = u[1] * v[2] - u[2] * v[1];
        w[1] = u[2] * v[0] - u[0] * v[2];
        w[2] = u[0] * v[1] - u[1] * v[0];
        area = 0.5 * sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
        for (a = corners ? 0 : 3; a < 6; a++) {
            double share = a < 3 ? area / 12.0 : (consistent ? area / 3.0 : area / 4.0);
            for (k = 0; k < count && nodes[k] != tri[a]; k++)
                ;
            if (k == count) {
                nodes[count] = tri[a];
                weights[count++] = 0.0;
            }
            weights[k] += share;
        }
    }
    return count;
}

/* Modes of the block with its two end interfaces: surfaces with `mpc` (node_sets == 0) or node
 * sets (given weights unless uniform); virtual nodes at the face centres. */
static int modes(int node_sets, int mpc, int uniform, int corners, int consistent, double scale,
                 double *hz)
{
    static int root[6 * 64], tip[6 * 64], nodes[2][MAX_NODES];
    static double weights[2][MAX_NODES];
    const double root_xv[3] = {0.0, 0.02, 0.015}, tip_xv[3] = {0.2, 0.02, 0.015};
    const int clamp[6] = {1, 1, 1, 1, 1, 1};
    ffrf_case *c = NULL;
    int n_root, n_tip, count = 0, m[2], k;
    n_root = end_faces(0.0, root);
    n_tip = end_faces(size_[0], tip);
    EXPECT(c, ffrf_case_new(&c), FFRF_OK, "");
    EXPECT(c, ffrf_case_add_body(c, "block", num_nodes, xyz, 10, NUM_TETS, tets, 2.1e11, 0.3,
           7850.0), FFRF_OK, "");
    if (node_sets) {
        m[0] = face_nodes(root, n_root, corners, consistent, nodes[0], weights[0]);
        m[1] = face_nodes(tip, n_tip, corners, consistent, nodes[1], weights[1]);
        for (k = 0; k < m[0]; k++)
            weights[0][k] *= scale;
        for (k = 0; k < m[1]; k++)
            weights[1][k] *= scale;
        EXPECT(c, ffrf_case_add_interface_nodes(c, 0, "root", FFRF_RBE3, m[0], nodes[0],
               uniform ? NULL : weights[0], root_xv, clamp), FFRF_OK, "");
        EXPECT(c, ffrf_case_add_interface_nodes(c, 0, "tip", FFRF_RBE3, m[1], nodes[1],
               uniform ? NULL : weights[1], tip_xv, NULL), FFRF_OK, "");
    } else {
        EXPECT(c, ffrf_case_add_surface(c, 0, "root", 6, n_root, root), FFRF_OK, "");
        EXPECT(c, ffrf_case_add_surface(c, 0, "tip", 6, n_tip, tip), FFRF_OK, "");
        EXPECT(c, ffrf_case_add_interface(c, 0, "root", mpc, root_xv, clamp), FFRF_OK, "");
        EXPECT(c, ffrf_case_add_interface(c, 0, "tip", mpc, tip_xv, NULL), FFRF_OK, "");
    }
    EXPECT(c, ffrf_case_set_num_modes(c, NUM_MODES), FFRF_OK, "");
    EXPECT(c, ffrf_case_run(c), FFRF_OK, "");
    EXPECT(c, ffrf_body_frequencies(c, 0, hz, NUM_MODES, &count), FFRF_OK, "");
    ffrf_case_close(c);
    return count;
}

/* Largest relative difference of two frequency lists. */
static double deviation(const double *a, const double *b)
{
    double worst = 0.0;
    int k;
    for (k = 0; k < NUM_MODES; k++)
        worst = fmax(worst, fabs(a[k] / b[k] - 1.0));
    return worst;
}

int main(void)
{
    double surface[NUM_MODES], node_set[NUM_MODES], area[NUM_MODES], consistent[NUM_MODES];
    double d;
    make_block();

    CHECK(modes(0, FFRF_RBE3, 1, 1, 0, 1.0, surface) == NUM_MODES);
    CHECK(modes(1, 0, 1, 1, 0, 1.0, node_set) == NUM_MODES);
    d = deviation(node_set, surface);
    printf("uniform: node set / surface - 1 = %.2e (f1 = %.3f Hz)\n", d, surface[0]);
    CHECK(d == 0.0);

    /* Weights equal to ffrf's to round-off (1e-16), not bitwise: the frequencies then agree to
     * the accuracy of the modal solver, shown by the same node set with its weights times 3,
     * mathematically the same interface (measured with one BLAS thread: tributary 1.2e-12,
     * consistent 2.6e-12, weights x 3 2.0e-12; threaded BLAS moves each by ~1e-12). */
    CHECK(modes(0, FFRF_RBE3_AREA, 0, 1, 0, 1.0, area) == NUM_MODES);
    CHECK(modes(1, 0, 0, 1, 0, 1.0, node_set) == NUM_MODES);
    d = deviation(node_set, area);
    printf("tributary area weights: node set / surface - 1 = %.2e\n", d);
    CHECK(d <= 1e-11);
    CHECK(modes(1, 0, 0, 1, 0, 3.0, surface) == NUM_MODES);
    d = deviation(node_set, surface);
    printf("  node set with weights x 3 / node set - 1 = %.2e (solver accuracy)\n", d);
    CHECK(d <= 1e-11);
    CHECK(modes(0, FFRF_RBE3, 1, 1, 0, 1.0, surface) == NUM_MODES);
    printf("area / uniform - 1: %.2e\n", deviation(area, surface));
    CHECK(deviation(area, surface) > 1e-3);

    CHECK(modes(0, FFRF_RBE3_AREA_CONSISTENT, 0, 1, 1, 1.0, consistent) == NUM_MODES);
    CHECK(modes(1, 0, 0, 0, 1, 1.0, node_set) == NUM_MODES);
    d = deviation(node_set, consistent);
    printf("consistent area weights: mid-side node set / surface - 1 = %.2e\n", d);
    CHECK(d <= 1e-11);
    printf("consistent / tributary - 1: %.2e\n", deviation(consistent, area));
    CHECK(deviation(consistent, area) > 1e-3);

    if (failures > 0) {
        fprintf(stderr, "%d failure(s)\n", failures);
        return 1;
    }
    printf("test_capi_node_sets: all checks passed\n");
    return 0;
}
