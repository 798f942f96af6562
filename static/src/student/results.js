// The EKF and odometry workbenches' runs (../ekf/workbench.js, ../odometry/workbench.js)
// import these builders from here, where the results view used to be; it lives in
// ../results/ now, and this file keeps those imports working until they name it.
export { element, link } from '../results/render.js';
