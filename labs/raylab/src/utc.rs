//! The system clock as a UTC calendar date and time, without a time-zone database.

/// Seconds since the Unix epoch, now (0 for a clock set before it).
pub fn now() -> u64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs())
}

/// `seconds` since the Unix epoch as `[year, month, day, hour, minute, second]` in UTC (the
/// proleptic Gregorian calendar, by the days-to-civil algorithm of Howard Hinnant).
pub fn date_time(seconds: u64) -> [i64; 6] {
    let days = (seconds / 86_400) as i64;
    let time = (seconds % 86_400) as i64;
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    [year, month, day, time / 3600, time % 3600 / 60, time % 60]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn known_instants() {
        assert_eq!(date_time(0), [1970, 1, 1, 0, 0, 0]);
        // 2000-02-29 12:34:56 UTC, a leap day in a year divisible by 400.
        assert_eq!(date_time(951_827_696), [2000, 2, 29, 12, 34, 56]);
        assert_eq!(date_time(1_798_761_599), [2026, 12, 31, 23, 59, 59]);
        // The day after 28 February 2100, which is no leap year.
        assert_eq!(date_time(4_107_542_400), [2100, 3, 1, 0, 0, 0]);
    }
}
