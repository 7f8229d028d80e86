//! Runs work on a rayon pool of a requested size (None: the global pool). Pools are cached.

use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

use rayon::ThreadPool;

fn pools() -> &'static Mutex<HashMap<usize, Arc<ThreadPool>>> {
    static POOLS: OnceLock<Mutex<HashMap<usize, Arc<ThreadPool>>>> = OnceLock::new();
    POOLS.get_or_init(|| Mutex::new(HashMap::new()))
}

pub fn run_with_threads<T: Send>(threads: Option<usize>, f: impl FnOnce() -> T + Send) -> Result<T, String> {
    match threads {
        None => Ok(f()),
        Some(n) => {
            let pool = {
                let mut map = pools().lock().map_err(|_| "thread-pool cache poisoned".to_string())?;
                match map.get(&n) {
                    Some(p) => p.clone(),
                    None => {
                        let p = Arc::new(
                            rayon::ThreadPoolBuilder::new().num_threads(n).build().map_err(|e| e.to_string())?,
                        );
                        map.insert(n, p.clone());
                        p
                    }
                }
            };
            Ok(pool.install(f))
        }
    }
}
