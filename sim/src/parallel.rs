//! Runs independent jobs on every core and hands their results on in the
//! order of the jobs, whatever the number of cores: sweeps and campaigns
//! print and write the same rows on any machine.

/// Calls `job` on each of `items`, shared out over the available cores, and
/// `each` with every result in item order as soon as it and every earlier
/// item's are in; returns the results in item order.
pub fn map_in_order<T: Sync, R: Send>(
    items: &[T],
    job: impl Fn(&T) -> R + Sync,
    mut each: impl FnMut(usize, &R),
) -> Vec<R> {
    let workers = std::thread::available_parallelism()
        .map_or(1, std::num::NonZeroUsize::get)
        .min(items.len())
        .max(1);
    let next = std::sync::atomic::AtomicUsize::new(0);
    let (send, receive) = std::sync::mpsc::channel();
    let mut slots: Vec<Option<R>> = items.iter().map(|_| None).collect();
    std::thread::scope(|scope| {
        for _ in 0..workers {
            let send = send.clone();
            let (next, job) = (&next, &job);
            scope.spawn(move || loop {
                let k = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                let Some(item) = items.get(k) else { break };
                if send.send((k, job(item))).is_err() {
                    break;
                }
            });
        }
        drop(send);
        let mut done = 0;
        for (k, result) in receive {
            if let Some(slot) = slots.get_mut(k) {
                *slot = Some(result);
            }
            while let Some(Some(result)) = slots.get(done) {
                each(done, result);
                done += 1;
            }
        }
    });
    slots.into_iter().flatten().collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn results_come_in_item_order() {
        let items: Vec<u64> = (0..40).collect();
        let mut seen = Vec::new();
        // Later items finish first: the order handed on is still the items'.
        let out = map_in_order(
            &items,
            |&i| {
                std::thread::sleep(std::time::Duration::from_micros(40 - i));
                i * i
            },
            |k, r| seen.push((k, *r)),
        );
        assert_eq!(out, items.iter().map(|i| i * i).collect::<Vec<_>>());
        assert_eq!(
            seen,
            items
                .iter()
                .map(|&i| (i as usize, i * i))
                .collect::<Vec<_>>()
        );
    }
}
