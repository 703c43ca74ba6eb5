package io.stridekit.tests

import io.stridekit.GnssFix
import io.stridekit.PaceException
import io.stridekit.PaceSample
import io.stridekit.PaceTracker
import io.stridekit.StepSample
import org.junit.jupiter.api.Test
import java.util.concurrent.CountDownLatch
import java.util.concurrent.Executors
import java.util.concurrent.TimeUnit
import java.util.concurrent.atomic.AtomicInteger
import java.util.concurrent.atomic.AtomicLong
import kotlin.test.assertEquals
import kotlin.test.assertTrue

/** Several threads calling one tracker: serialised, no crash, nothing lost. */
class ConcurrencyTest {
    @Test
    fun `four threads pushing into one tracker do not crash`() {
        val threads = 4
        val rounds = 300
        val clock = AtomicLong(0)
        val pushed = AtomicInteger(0)
        val accepted = AtomicInteger(0)
        val rejected = AtomicInteger(0)
        val unexpected = AtomicInteger(0)
        val start = CountDownLatch(1)
        val pool = Executors.newFixedThreadPool(threads)
        PaceTracker.withDefaults().use { tracker ->
            repeat(threads) { k ->
                pool.execute {
                    start.await()
                    try {
                        for (i in 0 until rounds) {
                            // Times come from a shared clock, but threads race between
                            // reading it and pushing: some samples arrive late and must be
                            // rejected with a PaceException, never crash.
                            val t = clock.incrementAndGet().toDouble() / 10.0
                            val fix = GnssFix(tS = t, latDeg = 50.0 + t * 2e-5, lonDeg = 18.0, horizontalAccuracyM = 5.0)
                            val step = StepSample.Count(tS = t, steps = (t * 3).toLong())
                            when (i % 4) {
                                0 -> try { tracker.pushFix(fix); accepted.incrementAndGet() } catch (e: PaceException) { rejected.incrementAndGet() }
                                1 -> try { tracker.pushSteps(step); accepted.incrementAndGet() } catch (e: PaceException) { rejected.incrementAndGet() }
                                2 -> {
                                    val r = tracker.pushSamples(listOf(PaceSample.Steps(step), PaceSample.Fix(fix)))
                                    rejected.addAndGet(r.rejected.size)
                                    accepted.addAndGet(2 - r.rejected.size)
                                    pushed.incrementAndGet() // two samples in this round
                                }
                                else -> {
                                    tracker.estimate()
                                    if (k == 0 && i % 40 == 3) PaceTracker.restore(tracker.snapshot()).close()
                                    pushed.decrementAndGet() // no sample in this round
                                }
                            }
                            pushed.incrementAndGet()
                        }
                    } catch (e: Throwable) {
                        unexpected.incrementAndGet()
                        e.printStackTrace()
                    }
                }
            }
            start.countDown()
            pool.shutdown()
            assertTrue(pool.awaitTermination(120, TimeUnit.SECONDS), "threads finished")
            assertEquals(0, unexpected.get(), "unexpected exceptions")
            assertEquals(pushed.get(), accepted.get() + rejected.get(), "every sample accepted or rejected")
            assertTrue(accepted.get() > 0)
            // The tracker is consistent: its state round-trips.
            PaceTracker.restore(tracker.snapshot()).use { assertEquals(tracker.estimate(), it.estimate()) }
        }
    }

    @Test
    fun `trackers on different threads are independent and deterministic`() {
        val run = Sim.run
        val pool = Executors.newFixedThreadPool(4)
        val results = (0 until 4).map { k ->
            pool.submit<List<io.stridekit.PaceEstimate>> {
                PaceTracker.withDefaults().use { t -> run.samples.chunked(17 + k * 50).flatMap { t.pushSamples(it).estimates } }
            }
        }.map { it.get(120, TimeUnit.SECONDS) }
        pool.shutdown()
        for (r in results) assertBitIdentical(run.referenceEstimates, r, "parallel trackers")
    }
}
