//! The learned odometry on the real indoor walks, for `eval pdr --data DIR`.

use crate::eval_pdr_real::MethodResult;
use crate::pdr_walks::Walk;

/// Methods of the learned odometry (none yet).
pub fn methods(_walks: &[Walk]) -> Result<Vec<MethodResult>, String> {
    Ok(Vec::new())
}
