package io.stridekit.tests

import io.stridekit.PhoneNavigator
import io.stridekit.PhonePlacement
import io.stridekit.simulatePhoneWalk
import org.junit.jupiter.api.Tag
import org.junit.jupiter.api.Test
import java.nio.ByteBuffer
import java.nio.ByteOrder

/**
 * Cost from Kotlin of the raw-event push (`PhoneNavigator.pushSensorEventsPacked`:
 * separate accelerometer, gyroscope and magnetometer events, 40-byte records, merged
 * in Rust) beside the merged-record push (`pushImuPacked`, 80-byte records), both in
 * batches of 1 000 records, packing excluded. Input: a simulated 100 Hz walk in hand;
 * as events, each sample is three events (the gyroscope 2 ms and the magnetometer
 * 4 ms after the accelerometer, as separate sensors report). Not part of the default
 * test run: `mvn -B -f tests/pom.xml test -Pbench -Dtest=SensorEventBenchTest
 * -Dstridekit.libdir=$PWD/target/release` after `cargo build --release -p stridekit`.
 */
@Tag("bench")
class SensorEventBenchTest {
    private val walk = simulatePhoneWalk(seed = 5uL, placement = PhonePlacement.IN_HAND, speedMps = 1.3, durationS = 300.0)
    private val minMeasureNanos = (System.getProperty("stridekit.bench.seconds") ?: "2").toDouble() * 1e9

    private fun measure(pass: () -> Unit): Double {
        var warm = 0L
        while (warm < minMeasureNanos / 3) {
            val t0 = System.nanoTime(); pass(); warm += System.nanoTime() - t0
        }
        var total = 0L
        var passes = 0
        while (total < minMeasureNanos || passes < 3) {
            val t0 = System.nanoTime(); pass(); total += System.nanoTime() - t0
            passes++
        }
        return total.toDouble() / passes
    }

    /** The walk's samples as events: accelerometer at t, gyroscope t + 2 ms, magnetometer t + 4 ms. */
    private fun events(): ByteArray {
        val src = ByteBuffer.wrap(walk.imuPacked).order(ByteOrder.LITTLE_ENDIAN)
        val n = walk.imuPacked.size / 80
        val out = ByteBuffer.allocate(n * 3 * 40).order(ByteOrder.LITTLE_ENDIAN)
        for (i in 0 until n) {
            val r = DoubleArray(10) { src.getDouble() }
            out.putDouble(r[0]).putLong(1).putDouble(r[1]).putDouble(r[2]).putDouble(r[3])
            out.putDouble(r[0] + 0.002).putLong(4).putDouble(r[4]).putDouble(r[5]).putDouble(r[6])
            out.putDouble(r[0] + 0.004).putLong(2).putDouble(r[7]).putDouble(r[8]).putDouble(r[9])
        }
        return out.array()
    }

    @Test
    fun `raw-event push against merged-record push, per event and per sample`() {
        val samples = walk.imuPacked.size / 80
        val events = events()
        val nEvents = events.size / 40
        val batch = 1000
        val imuChunks = (0 until samples step batch).map { walk.imuPacked.copyOfRange(it * 80, minOf(samples, it + batch) * 80) }
        val eventChunks = (0 until nEvents step batch).map { events.copyOfRange(it * 40, minOf(nEvents, it + batch) * 40) }
        val merged = measure { PhoneNavigator.withDefaults().use { nav -> for (c in imuChunks) nav.pushImuPacked(c) } }
        val raw = measure {
            PhoneNavigator.withDefaults().use { nav ->
                for (c in eventChunks) nav.pushSensorEventsPacked(c)
                nav.flushSensorEvents()
            }
        }
        println()
        println("PhoneNavigator, $samples samples = $nEvents events per pass (simulated 100 Hz walk in hand, magnetometer), batches of $batch records, library in ${System.getProperty("jna.library.path")}")
        println()
        println("| push | ns per record | ns per IMU sample |")
        println("|---|---:|---:|")
        println(String.format("| pushImuPacked (80-byte merged records) | %.0f | %.0f |", merged / samples, merged / samples))
        println(String.format("| pushSensorEventsPacked (40-byte events, 3 per sample) | %.0f | %.0f |", raw / nEvents, raw / samples))
        println()
    }
}
