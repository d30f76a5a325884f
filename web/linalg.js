// linalg.js: the small linear algebra the lab's specs need, in plain JavaScript (window.linalg).
//
//   linalg.singularValues(A, rows, cols)   A flat, row-major; the min(rows, cols) singular values,
//                                          largest first
//
// One-sided Jacobi (Hestenes): rotate pairs of columns of B = A^T until every pair is orthogonal;
// then the columns' lengths are A's singular values. Unlike the eigenvalues of A A^T, it keeps the
// small singular values accurate (to about eps * sigma_max instead of sqrt(eps) * sigma_max), which
// is what a readout of the distance to a singular pose needs. Small and dense: a 6 x 7 Jacobian
// converges in a handful of sweeps.
(function (root) {
  'use strict';

  function singularValues(A, rows, cols) {
    if (!(rows > 0 && cols > 0) || A.length !== rows * cols) {
      throw new Error('singularValues: A has ' + A.length + ' entries, not ' + rows + ' x ' + cols);
    }
    // B = A^T as columns: column i of B is row i of A, of length cols (the shorter side counts)
    const transpose = rows <= cols;
    const n = transpose ? rows : cols;  // number of singular values
    const m = transpose ? cols : rows;  // length of each column
    const column = [];
    for (let i = 0; i < n; i++) {
      const c = new Float64Array(m);
      for (let k = 0; k < m; k++) c[k] = transpose ? A[i * cols + k] : A[k * cols + i];
      column.push(c);
    }
    const eps = 1e-15;
    for (let sweep = 0; sweep < 60; sweep++) {
      let rotated = false;
      for (let i = 0; i < n - 1; i++) {
        for (let j = i + 1; j < n; j++) {
          const a = column[i];
          const b = column[j];
          let alpha = 0;
          let beta = 0;
          let gamma = 0;
          for (let k = 0; k < m; k++) {
            alpha += a[k] * a[k];
            beta += b[k] * b[k];
            gamma += a[k] * b[k];
          }
          if (Math.abs(gamma) <= eps * Math.sqrt(alpha * beta)) continue;
          rotated = true;
          // the rotation that makes columns i and j orthogonal (the smaller root, for stability)
          const zeta = (beta - alpha) / (2 * gamma);
          const t = Math.sign(zeta || 1) / (Math.abs(zeta) + Math.sqrt(1 + zeta * zeta));
          const c = 1 / Math.sqrt(1 + t * t);
          const s = c * t;
          for (let k = 0; k < m; k++) {
            const x = a[k];
            const y = b[k];
            a[k] = c * x - s * y;
            b[k] = s * x + c * y;
          }
        }
      }
      if (!rotated) break;
    }
    return column.map((c) => Math.hypot(...c)).sort((x, y) => y - x);
  }

  root.linalg = {singularValues};
  if (typeof module !== 'undefined' && module.exports) module.exports = root.linalg;
})(typeof window !== 'undefined' ? window : globalThis);
