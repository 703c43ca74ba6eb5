package io.stridekit.tests

import java.io.File
import java.nio.ByteBuffer
import java.nio.ByteOrder
import java.util.zip.GZIPInputStream

/**
 * An Android sensor log of `../shared/data/phone-indoor`, read in Kotlin as an app that
 * logged it would (shared by the PDR and map tests): its IMU samples packed as 80-byte
 * records and its surveyed waypoints.
 */
object AndroidLog {
    /** Bytes of one packed IMU record: t, accel xyz, gyro xyz, mag xyz (f64, little-endian). */
    const val RECORD_BYTES = 80

    /** Gyroscope and magnetometer events are held this long past their ends, s. */
    private const val HOLD_S = 0.1

    /** `phone-indoor` under `STRIDEKIT_DATA` (or `-Dstridekit.data`), when set. */
    fun dataDir(): File? =
        (System.getenv("STRIDEKIT_DATA") ?: System.getProperty("stridekit.data"))?.let { File(it, "phone-indoor") }

    /** A log: the packed IMU records and the waypoints (t s, x m, y m). */
    class Log(val packedImu: ByteArray, val waypoints: List<DoubleArray>)

    /**
     * The log's IMU samples as packed records, built as the Rust reader does: at the
     * accelerometer's times, gyroscope and magnetometer interpolated linearly between
     * their events around it (held [HOLD_S] past the ends); and its waypoints.
     */
    fun read(file: File): Log {
        val acc = ArrayList<DoubleArray>()
        val gyr = ArrayList<DoubleArray>()
        val mag = ArrayList<DoubleArray>()
        val wp = ArrayList<DoubleArray>()
        GZIPInputStream(file.inputStream()).bufferedReader().useLines { lines ->
            for (line in lines) {
                if (line.isBlank() || line.startsWith("#")) continue
                val f = line.trim().split(Regex("\\s+"))
                val t = f[0].toDouble() / 1000.0
                when (f[1]) {
                    "TYPE_ACCELEROMETER" -> acc.add(doubleArrayOf(t, f[2].toDouble(), f[3].toDouble(), f[4].toDouble()))
                    "TYPE_GYROSCOPE" -> gyr.add(doubleArrayOf(t, f[2].toDouble(), f[3].toDouble(), f[4].toDouble()))
                    "TYPE_MAGNETIC_FIELD" -> mag.add(doubleArrayOf(t, f[2].toDouble(), f[3].toDouble(), f[4].toDouble()))
                    "TYPE_WAYPOINT" -> wp.add(doubleArrayOf(t, f[2].toDouble(), f[3].toDouble()))
                }
            }
        }
        gyr.sortBy { it[0] }
        mag.sortBy { it[0] }
        val out = ByteBuffer.allocate(acc.size * RECORD_BYTES).order(ByteOrder.LITTLE_ENDIAN)
        var n = 0
        for (a in acc) {
            val g = at(gyr, a[0]) ?: continue
            val m = at(mag, a[0]) ?: doubleArrayOf(Double.NaN, Double.NaN, Double.NaN)
            out.putDouble(a[0])
            for (j in 1..3) out.putDouble(a[j])
            g.forEach { out.putDouble(it) }
            m.forEach { out.putDouble(it) }
            n++
        }
        return Log(out.array().copyOf(n * RECORD_BYTES), wp)
    }

    /** The time of packed record `i`, s. */
    fun timeOf(packed: ByteArray, i: Int): Double =
        ByteBuffer.wrap(packed, i * RECORD_BYTES, 8).order(ByteOrder.LITTLE_ENDIAN).double

    /** The xyz of stream `s` (t, x, y, z rows sorted by t) at `t`: interpolated, or null. */
    private fun at(s: List<DoubleArray>, t: Double): DoubleArray? {
        if (s.isEmpty()) return null
        val i = s.indexOfLast { it[0] <= t }
        if (i < 0) return if (s[0][0] - t <= HOLD_S) s[0].copyOfRange(1, 4) else null
        val a = s[i]
        val b = s.getOrNull(i + 1)
        if (b == null || b[0] <= a[0]) return if (t - a[0] <= HOLD_S) a.copyOfRange(1, 4) else null
        val k = (t - a[0]) / (b[0] - a[0])
        return DoubleArray(3) { a[it + 1] + k * (b[it + 1] - a[it + 1]) }
    }
}
